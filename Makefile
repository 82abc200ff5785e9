# The two commands of the README, and a few helpers. Everything goes through CMake presets;
# this file only sequences them.
PRESET ?= release
JOBS ?= $(shell nproc)
BUILD := build/$(PRESET)
PROBELESS := $(BUILD)/app/probeless

.PHONY: all setup configure build test test-asan fuzz demo demo-calibrate bench package format clean

all: build

setup:
	@scripts/setup.sh

$(BUILD)/build.ninja: CMakeLists.txt CMakePresets.json
	cmake --preset $(PRESET)

configure: setup $(BUILD)/build.ninja

build: configure
	cmake --build --preset $(PRESET) -j $(JOBS)

test: build
	ctest --preset $(PRESET) -j $(JOBS)

test-asan:
	$(MAKE) test PRESET=asan

# The libFuzzer targets of tests/fuzz/ (clang, ASan + UBSan; docs/security.md "Fuzzing"),
# each run for FUZZ_SECONDS; FUZZ_TARGETS="png gltf" runs some only. Inputs that fail are
# left in build/fuzz/crashes/<name>/, and the target fails.
FUZZ_SECONDS ?= 60
FUZZ_TARGETS ?=
# FUZZ_RUNS=1000000: stop each target after that many inputs (if before FUZZ_SECONDS).
FUZZ_RUNS ?=
fuzz:
	cmake --preset fuzz
	cmake --build --preset fuzz -j $(JOBS)
	FUZZ_RUNS=$(FUZZ_RUNS) tests/fuzz/run_fuzz.sh build/fuzz $(FUZZ_SECONDS) $(FUZZ_TARGETS)

demo: build
	$(PROBELESS) run

# Bring-up on the synthetic rig (docs/calibration.md "Checked on the sim"): record the sim's
# calibration views of its ChArUco board with both cameras, calibrate the rig from them, and
# compare what was recovered with the recording's true calibration.
DEMO_CALIB := $(BUILD)/demo-calibrate
demo-calibrate: build
	rm -rf $(DEMO_CALIB) && mkdir -p $(DEMO_CALIB)
	$(PROBELESS) record --source sim:trajectory=calibration,fps=1,fisheye_fps=1,realtime=0,fisheye_size=1024 --frames 53 $(DEMO_CALIB)/rec
	$(PROBELESS) calibrate --recording $(DEMO_CALIB)/rec --board charuco:5x4:80:60:4x4_50 --out $(DEMO_CALIB)/rig.toml --json $(DEMO_CALIB)/rig.json --views-out $(DEMO_CALIB)/views
	@echo "recovered: $(DEMO_CALIB)/rig.toml, corners per view: $(DEMO_CALIB)/views/, truth: $(DEMO_CALIB)/rec/calibration.toml"

bench: build
	$(PROBELESS) bench sim

# The Debian package (docs/appliance.md): build/release/probeless_<version>_<arch>.deb
package: build
	cd $(BUILD) && cpack

format:
	git ls-files '*.cpp' '*.hpp' '*.cl' | xargs clang-format -i

clean:
	rm -rf build
