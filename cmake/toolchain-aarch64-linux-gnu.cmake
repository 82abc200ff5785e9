# Cross compiling for 64-bit Arm Linux (Raspberry Pi 5, RK3588) with Debian's
# crossbuild-essential-arm64 and arm64 libraries installed through multiarch
# (`dpkg --add-architecture arm64`; docs/boards.md "The arm64 cross build").
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
# Multiarch keeps arm64 libraries beside the host's under /usr, in lib/aarch64-linux-gnu:
# this makes every find_* look there (and for CMake packages in its cmake/), not in the
# host's lib/x86_64-linux-gnu. Headers under /usr/include are shared by both.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# pkg-config must read the arm64 .pc files only, never the host's. The first inclusion
# decides: try_compile includes this file again in the same process (the environment is
# shared) with its scratch directory as CMAKE_BINARY_DIR, which must not replace the
# OpenEXR stand-in's place under the real build tree.
if(NOT "$ENV{PKG_CONFIG_LIBDIR}" MATCHES "/arm64-openexr$")
  set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)
  set(ENV{PKG_CONFIG_PATH} "")
  include(${CMAKE_CURRENT_LIST_DIR}/arm64-openexr.cmake)
endif()

# Tests run under QEMU's user-mode emulator: ctest prefixes every test command with it, and
# gtest_discover_tests lists the tests through it. libc6:arm64 (multiarch) puts the arm64
# loader at /lib/ld-linux-aarch64.so.1 and its libraries under /usr/lib/aarch64-linux-gnu,
# so the emulator needs no separate root (-L).
find_program(PROBELESS_QEMU_AARCH64 qemu-aarch64-static)
if(PROBELESS_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${PROBELESS_QEMU_AARCH64})
endif()
