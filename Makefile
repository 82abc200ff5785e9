# The two commands of the README, and a few helpers. Everything goes through CMake presets;
# this file only sequences them.
PRESET ?= release
JOBS ?= $(shell nproc)
BUILD := build/$(PRESET)
PROBELESS := $(BUILD)/app/probeless

.PHONY: all setup configure build test test-asan fuzz demo bench package format clean

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

bench: build
	$(PROBELESS) bench sim

# The Debian package (docs/appliance.md): build/release/probeless_<version>_<arch>.deb
package: build
	cd $(BUILD) && cpack

format:
	git ls-files '*.cpp' '*.hpp' '*.cl' | xargs clang-format -i

clean:
	rm -rf build
