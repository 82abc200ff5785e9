# The two commands of the README, and a few helpers. Everything goes through CMake presets;
# this file only sequences them.
PRESET ?= release
JOBS ?= $(shell nproc)
BUILD := build/$(PRESET)
PROBELESS := $(BUILD)/app/probeless

.PHONY: all setup configure build test test-asan demo bench package format clean

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
