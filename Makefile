# The two commands of the README, and a few helpers. Everything goes through CMake presets;
# this file only sequences them.
PRESET ?= release
JOBS ?= $(shell nproc)
BUILD := build/$(PRESET)
PROBELESS := $(BUILD)/app/probeless

.PHONY: all setup configure build test test-asan fuzz demo demo-calibrate bench deb package format clean

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

# The Debian packages (docs/appliance.md "The Debian packages"): debian/rules packages the
# tree `build` has just built (no second compile inside dpkg-buildpackage) and writes
# probeless_<version>_<arch>.deb, probeless-lab_... and their -dbgsym .ddebs, the .changes and
# the .buildinfo to $(DEB_DIR), inside the build tree rather than the checkout's parent.
DEB_DIR := $(BUILD)/deb
DEB_VERSION = $(shell dpkg-parsechangelog -S Version)
DEB_ARCH = $(shell dpkg --print-architecture)
deb: build
	rm -rf $(DEB_DIR) && mkdir -p $(DEB_DIR)
	PROBELESS_BUILD_DIR=$(BUILD) PROBELESS_DEB_DIR=$(DEB_DIR) dpkg-buildpackage -b --no-sign \
	  --changes-option=-u$(DEB_DIR) --buildinfo-option=-u$(DEB_DIR) \
	  --changes-file=$(DEB_DIR)/probeless_$(DEB_VERSION)_$(DEB_ARCH).changes \
	  --buildinfo-file=$(DEB_DIR)/probeless_$(DEB_VERSION)_$(DEB_ARCH).buildinfo
	lintian --fail-on error $(DEB_DIR)/*.deb
	@ls -l $(DEB_DIR)/*.deb

# The old name of `make deb`.
package: deb

format:
	git ls-files '*.cpp' '*.hpp' '*.cl' | xargs clang-format -i

clean:
	rm -rf build
