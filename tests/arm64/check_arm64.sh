#!/usr/bin/env bash
# The arm64 cross build and its tests under QEMU user mode (docs/boards.md), as one ctest:
#   check_arm64.sh SOURCE_DIR BUILD_DIR
# Configures BUILD_DIR with the arm64 preset (base, core, drivers and kernels, cross compiled by
# crossbuild-essential-arm64 against multiarch arm64 libraries), builds it (ccache when
# present) and runs its ctest, every test binary through qemu-aarch64-static.
# Exit 77 (skip) when the toolchain, the arm64 libraries or QEMU are missing.
set -euo pipefail
src=${1:?source dir}
build=${2:?build dir}
jobs=${PROBELESS_ARM64_JOBS:-2}

skip() { echo "arm64: SKIP: $*"; exit 77; }
command -v aarch64-linux-gnu-g++ >/dev/null || skip "no aarch64-linux-gnu-g++ (crossbuild-essential-arm64; scripts/setup.sh installs it)"
command -v qemu-aarch64-static >/dev/null || skip "no qemu-aarch64-static (qemu-user-static)"
[[ -e /lib/ld-linux-aarch64.so.1 ]] || skip "no arm64 loader /lib/ld-linux-aarch64.so.1 (libc6:arm64 through multiarch)"
for f in /usr/lib/aarch64-linux-gnu/libgtest.a /usr/lib/aarch64-linux-gnu/libOpenCL.so \
  /usr/lib/aarch64-linux-gnu/cmake/tomlplusplus /usr/lib/aarch64-linux-gnu/libspdlog.so \
  /usr/lib/aarch64-linux-gnu/libgpiodcxx.so /usr/lib/aarch64-linux-gnu/libOpenEXR-3_1.so.30; do
  [[ -e $f ]] || skip "no $f: the arm64 libraries of scripts/packages.txt (':arm64') are not installed"
done

if command -v ccache >/dev/null; then
  export CMAKE_CXX_COMPILER_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER:-ccache}
  export CMAKE_C_COMPILER_LAUNCHER=${CMAKE_C_COMPILER_LAUNCHER:-ccache}
fi
# Hits across worktrees and build dirs need paths relative to a common base.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$(dirname "$(cd "$src" && pwd)")}
start=$(date +%s)
# BUILD_DIR is the preset's own build/arm64, shared with `cmake --preset arm64` by hand:
# ccache's hits need the same paths relative to the build directory, so a tree elsewhere
# would compile everything again. Two test runs (release and asan trees) take turns.
mkdir -p "$build"
exec 9>"$build.lock"
flock 9
cmake --preset arm64 -S "$src" -B "$build" >"$build.configure.log" 2>&1 ||
  { cat "$build.configure.log"; exit 1; }
configured=$(date +%s)
nice cmake --build "$build" -j "$jobs"
built=$(date +%s)
ctest --test-dir "$build" -j "$jobs" --output-on-failure --no-tests=error --timeout 300
tested=$(date +%s)
echo "arm64: configure $((configured - start)) s, build $((built - configured)) s," \
  "tests under qemu-user $((tested - built)) s"
