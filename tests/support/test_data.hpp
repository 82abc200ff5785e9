#pragma once
// Where tests find ../shared/data and scratch space. Tests that need the shared data call
// PROBELESS_REQUIRE_DATA("sub/dir") and are skipped with a message when it is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace probeless::testing {

// $PROBELESS_DATA, else the path configured at build time; empty when it does not exist.
std::filesystem::path shared_data_dir();
// A fresh empty directory under the build tree, unique per test.
std::filesystem::path scratch_dir();

}  // namespace probeless::testing

#define PROBELESS_REQUIRE_DATA(sub)                                                          \
  do {                                                                                       \
    const auto _dir = ::probeless::testing::shared_data_dir();                               \
    if (_dir.empty() || !std::filesystem::exists(_dir / (sub)))                              \
      GTEST_SKIP() << "shared data not found: " << (sub)                                     \
                   << " (set PROBELESS_DATA to ../shared/data to run this test)";            \
  } while (0)
