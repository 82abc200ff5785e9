# OpenEXR for the arm64 cross build without libopenexr-dev:arm64, which Debian 12 cannot
# install beside the host's libopenexr-dev (it is not Multi-Arch: same). What the -dev
# package adds to the runtime library is architecture-independent headers (the host's
# /usr/include/OpenEXR; Debian 12's amd64 and arm64 copies are byte-identical), the
# unversioned .so links and OpenEXR.pc. This makes the last two under the build tree,
# pointing at libopenexr-3-1-30:arm64, and puts them on pkg-config's path. Included by the
# toolchain file; does nothing when a real arm64 OpenEXR.pc exists.
set(_exr_arch_dir /usr/lib/aarch64-linux-gnu)
set(_exr_shim ${CMAKE_BINARY_DIR}/arm64-openexr)
if(NOT EXISTS ${_exr_arch_dir}/pkgconfig/OpenEXR.pc AND EXISTS ${_exr_arch_dir}/libOpenEXR-3_1.so.30
   AND EXISTS /usr/include/OpenEXR/ImfRgbaFile.h)
  file(MAKE_DIRECTORY ${_exr_shim}/lib)
  foreach(lib OpenEXR OpenEXRUtil OpenEXRCore Iex IlmThread)
    file(CREATE_LINK ${_exr_arch_dir}/lib${lib}-3_1.so.30 ${_exr_shim}/lib/lib${lib}-3_1.so SYMBOLIC)
  endforeach()
  file(WRITE ${_exr_shim}/OpenEXR.pc
"# Written by cmake/arm64-openexr.cmake: libopenexr-3-1-30:arm64 with the host's headers.
libdir=${_exr_shim}/lib
includedir=/usr/include
Name: OpenEXR
Description: OpenEXR image library (arm64 runtime, shared headers)
Version: 3.1.5
Libs: -L\${libdir} -lOpenEXR-3_1 -lOpenEXRUtil-3_1 -lOpenEXRCore-3_1 -lIex-3_1 -lIlmThread-3_1
Cflags: -I\${includedir} -I\${includedir}/OpenEXR -pthread
Requires: Imath
")
  set(ENV{PKG_CONFIG_LIBDIR} "$ENV{PKG_CONFIG_LIBDIR}:${_exr_shim}")
endif()
