#include "kernels/envmap/envmap_downsample.hpp"

#include <gtest/gtest.h>

#include <random>

#include "envmap_test_support.hpp"
#include "support/cl_context.hpp"

namespace probeless::envmap {
namespace {

using namespace envmap::testing;
using probeless::testing::cl_context;

TEST(EnvmapDownsample, MatchesTheReference) {
  std::mt19937 rng(2);
  auto& ctx = cl_context();
  EnvmapDownsample stage(ctx);
  for (const auto& [n, m] : std::vector<std::pair<int, int>>{{1, 1}, {6, 3}, {15, 5}, {128, 32}}) {
    const ImageRGBAF in = random_texels(rng, n);
    const DeviceImage<float, 4> d(ctx, in);
    DeviceImage<float, 4> out;
    stage.run(d, m, out);
    EXPECT_EQ(count_mismatches(out.download(ctx.queue()), envmap_downsample_reference(in, m)), 0)
        << n << " -> " << m;
  }
  DeviceImage<float, 4> out;
  EXPECT_THROW(stage.run(DeviceImage<float, 4>(ctx, make_texels(10)), 3, out),
               std::invalid_argument);
}

TEST(EnvmapDownsample, AveragesBlocks) {
  ImageRGBAF in = make_texels(2);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 2; ++x) in.at(x, y, 0) = static_cast<float>(x + 2 * y);
  const ImageRGBAF out = envmap_downsample_reference(in, 1);
  EXPECT_FLOAT_EQ(out.at(0, 0, 0), 1.5F);   // 0 1 2 3
  EXPECT_FLOAT_EQ(out.at(0, 5, 0), 21.5F);  // 20 21 22 23
}

}  // namespace
}  // namespace probeless::envmap
