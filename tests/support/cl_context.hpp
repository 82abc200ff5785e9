#pragma once
// One ComputeContext per test binary: PoCL compiles each program once per context, so tests
// share it (programs are cached in memory by source and options). The device follows
// PROBELESS_CL_PLATFORM / PROBELESS_CL_DEVICE like the service; PoCL by default.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "kernels/runtime/compute_context.hpp"

namespace probeless::testing {

inline ComputeContext& cl_context() {
  static const std::unique_ptr<ComputeContext> ctx = std::make_unique<ComputeContext>();
  return *ctx;
}

// Sizes every kernel test runs on: single pixel, odd widths and heights, a VGA frame and
// one less than it in both directions (partial work-groups at the right and bottom).
inline const std::vector<std::pair<int, int>>& kernel_test_sizes() {
  static const std::vector<std::pair<int, int>> sizes{{1, 1},  {17, 3},    {3, 17},   {33, 1},
                                                      {1, 29}, {641, 479}, {640, 480}};
  return sizes;
}

}  // namespace probeless::testing
