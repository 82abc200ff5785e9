# The tests of a build with only some layers (PROBELESS_LAYERS; the arm64 cross build of
# docs/boards.md). A test file is built when every project header it includes belongs to a
# layer that is built, it needs no OpenCL device (the target's OpenCL driver, PoCL, cannot
# be installed beside the host's, so kernel tests that run a device stay native) and it does
# not run the `probeless` binary (app/). Under an emulator, tests of the synthetic rig are
# left out too (see below).
# Selected files are grouped per folder into test_<kind>_<area>, named as in the full build.
add_library(probeless_testing OBJECT support/test_data.cpp)
target_compile_definitions(probeless_testing PRIVATE
  "PROBELESS_TEST_DATA=\"${PROBELESS_DATA_DIR}\""
  "PROBELESS_TEST_BUILD_DIR=\"${PROJECT_BINARY_DIR}\""
  "PROBELESS_TEST_BINARY=\"\"")
target_link_libraries(probeless_testing PUBLIC probeless_core GTest::gtest GTest::gmock)
target_include_directories(probeless_testing PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})

set(layer_libraries)
foreach(layer IN LISTS PROBELESS_LAYERS)
  list(APPEND layer_libraries probeless_${layer})
endforeach()

# Whether `file` can be built and run here ("YES", else the reason). Headers beside it
# (`#include "name.hpp"`) are read too: test fixtures include the layers they need.
function(probeless_subset_test_fits file out_fits)
  get_filename_component(dir_of_file ${file} DIRECTORY)
  file(STRINGS ${file} includes REGEX "^#include \"[^\"]+\"")
  foreach(line IN LISTS includes)
    string(REGEX MATCH "\"([^\"]+)\"" _ "${line}")
    set(path ${CMAKE_MATCH_1})
    if(NOT path MATCHES "/")
      probeless_subset_test_fits(${dir_of_file}/${path} local_fits)
      if(NOT local_fits STREQUAL "YES")
        set(${out_fits} "${local_fits} (through ${path})" PARENT_SCOPE)
        return()
      endif()
      continue()
    endif()
    string(REGEX MATCH "^([a-z_]+)/(.*)$" _ "${path}")
    set(dir ${CMAKE_MATCH_1})
    set(header ${CMAKE_MATCH_2})
    if(dir STREQUAL "support")
      if(NOT header STREQUAL "test_data.hpp")
        set(${out_fits} "needs tests/support/${header}" PARENT_SCOPE)
        return()
      endif()
    elseif(NOT dir IN_LIST PROBELESS_LAYERS)
      set(${out_fits} "needs ${dir}/" PARENT_SCOPE)
      return()
    elseif(path MATCHES "^drivers/libcamera/" AND NOT PROBELESS_HAVE_LIBCAMERA)
      set(${out_fits} "needs libcamera (not found for this build)" PARENT_SCOPE)
      return()
    elseif(CMAKE_CROSSCOMPILING_EMULATOR AND path MATCHES "^drivers/sim/")
      # The synthetic rig ray-traces its world: natively seconds, under QEMU minutes per
      # test (7.5 of the 8.7 CPU-minutes of the emulated run), for code with nothing
      # board-specific in it.
      set(${out_fits} "runs the synthetic rig (too slow emulated)" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  file(STRINGS ${file} device_uses REGEX "ComputeContext|cl_context")
  if(device_uses)
    set(${out_fits} "needs an OpenCL device" PARENT_SCOPE)
    return()
  endif()
  file(STRINGS ${file} cli_uses REGEX "PROBELESS_BINARY")
  if(cli_uses)
    set(${out_fits} "runs the probeless CLI (app/)" PARENT_SCOPE)
    return()
  endif()
  set(${out_fits} YES PARENT_SCOPE)
endfunction()

set(subset_files 0)
set(skipped_files 0)
foreach(kind unit kernels integration)
  file(GLOB areas LIST_DIRECTORIES true ${CMAKE_CURRENT_SOURCE_DIR}/${kind}/*)
  foreach(area_dir IN LISTS areas)
    if(NOT IS_DIRECTORY ${area_dir})
      continue()
    endif()
    get_filename_component(area ${area_dir} NAME)
    file(GLOB candidates CONFIGURE_DEPENDS ${area_dir}/*.cpp)
    set(test_sources)
    foreach(file IN LISTS candidates)
      probeless_subset_test_fits(${file} fits)
      if(fits STREQUAL "YES")
        list(APPEND test_sources ${file})
        math(EXPR subset_files "${subset_files} + 1")
      else()
        math(EXPR skipped_files "${skipped_files} + 1")
        file(RELATIVE_PATH rel ${CMAKE_CURRENT_SOURCE_DIR} ${file})
        message(VERBOSE "layer subset: not building ${rel}: ${fits}")
      endif()
    endforeach()
    if(NOT test_sources)
      continue()
    endif()
    set(exe test_${kind}_${area})
    add_executable(${exe} ${test_sources})
    target_link_libraries(${exe} PRIVATE probeless_testing ${layer_libraries} GTest::gtest_main)
    target_compile_definitions(${exe} PRIVATE "PROBELESS_TEST_SOURCE_DIR=\"${area_dir}\"")
    probeless_warnings(${exe})
    # Listing the tests runs the binary (through CMAKE_CROSSCOMPILING_EMULATOR when cross
    # compiling); QEMU's start-up makes that slower than natively.
    gtest_discover_tests(${exe} TEST_PREFIX "${kind}.${area}." DISCOVERY_TIMEOUT 120
      PROPERTIES LABELS "${kind};subset")
  endforeach()
endforeach()
message(STATUS "Layer subset (${PROBELESS_LAYERS}): ${subset_files} test files built, "
               "${skipped_files} left to the full build (--log-level=VERBOSE says why)")

add_test(NAME layering COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/check_layering.sh
  ${PROJECT_SOURCE_DIR})
