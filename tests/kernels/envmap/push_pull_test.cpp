#include "kernels/envmap/push_pull.hpp"

#include <gtest/gtest.h>

#include <random>

#include "envmap_test_support.hpp"
#include "kernels/envmap/push_pull_reference.hpp"
#include "support/cl_context.hpp"

namespace probeless::envmap {
namespace {

using namespace envmap::testing;
using probeless::testing::cl_context;

// Random texels with a given set of faces holding observations (about a third of their
// texels), the rest unobserved with stale values.
ImageRGBAF sparse_texels(std::mt19937& rng, int n, int faces_with_data) {
  ImageRGBAF t = random_texels(rng, n);
  std::uniform_real_distribution<float> pick(0, 1);
  for (int row = 0; row < 6 * n; ++row)
    for (int x = 0; x < n; ++x) {
      const bool data = (faces_with_data >> (row / n) & 1) && pick(rng) < 0.35F;
      if (!data)
        t.at(x, row, 3) = 0.0F;
      else if (t.at(x, row, 3) == 0.0F)
        t.at(x, row, 3) = 0.1F;
    }
  return t;
}

ImageRGBAF device_fill(PushPull& stage, const ImageRGBAF& texels, int* observed = nullptr) {
  auto& ctx = cl_context();
  DeviceImage<float, 4> d(ctx, texels);
  stage.fill(d);
  if (observed) *observed = stage.observed_faces();
  return d.download(ctx.queue());
}

TEST(PushPull, AdjacentFaces) {
  EXPECT_EQ(adjacent_faces(0), 0b111100);
  EXPECT_EQ(adjacent_faces(1), 0b111100);
  EXPECT_EQ(adjacent_faces(3), 0b110011);
  EXPECT_EQ(adjacent_faces(4), 0b001111);
}

TEST(PushPull, MatchesTheReferenceOnRandomSizesAndFaceSets) {
  std::mt19937 rng(11);
  PushPull stage(cl_context());
  for (int n : {1, 2, 5, 16, 33, 128}) {
    for (int faces : {0x3F, 0x2F, 0x10, 0x05, 0x00}) {
      const ImageRGBAF in = sparse_texels(rng, n, faces);
      int device_mask = -1;
      const ImageRGBAF got = device_fill(stage, in, &device_mask);
      ImageRGBAF want = in;
      const int mask = push_pull_reference(want);
      EXPECT_EQ(device_mask, mask) << n;
      EXPECT_EQ(count_mismatches(got, want), 0) << n << " faces " << faces;
    }
  }
}

TEST(PushPull, ObservedTexelsNeverChange) {
  std::mt19937 rng(5);
  PushPull stage(cl_context());
  for (int n : {7, 64}) {
    const ImageRGBAF in = sparse_texels(rng, n, 0x1B);
    const ImageRGBAF out = device_fill(stage, in);
    int observed = 0;
    for (int row = 0; row < 6 * n; ++row)
      for (int x = 0; x < n; ++x) {
        if (in.at(x, row, 3) != 0.0F) {
          ++observed;
          for (int c = 0; c < 4; ++c) ASSERT_EQ(out.at(x, row, c), in.at(x, row, c));
        } else {
          ASSERT_EQ(out.at(x, row, 3), 0.0F);  // filled texels stay unobserved
        }
      }
    EXPECT_GT(observed, 0);
  }
}

TEST(PushPull, FillsFacesWithNoData) {
  PushPull stage(cl_context());
  const int n = 32;
  // Only the top face (+Z) observed, constant 4: every face gets it, the bottom one through
  // its four neighbours in a second pass.
  ImageRGBAF in = make_texels(n);
  for (int row = 0; row < 6 * n; ++row)
    for (int x = 0; x < n; ++x) {
      const bool top = row / n == 4;
      for (int c = 0; c < 3; ++c) in.at(x, row, c) = top ? 4.0F : -1.0F;
      in.at(x, row, 3) = top ? 1.0F : 0.0F;
    }
  int observed = 0;
  const ImageRGBAF out = device_fill(stage, in, &observed);
  EXPECT_EQ(observed, 1 << 4);
  for (int row = 0; row < 6 * n; ++row)
    for (int x = 0; x < n; ++x)
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(out.at(x, row, c), 4.0F, 1e-5F) << x << " " << row;

  // A gradient on the four side faces: the empty top and bottom are filled from their
  // borders, so each takes values between the extremes and is not constant.
  ImageRGBAF side = make_texels(n);
  for (int row = 0; row < 6 * n; ++row)
    for (int x = 0; x < n; ++x) {
      const bool data = row / n < 4;
      for (int c = 0; c < 3; ++c) side.at(x, row, c) = data ? 1.0F + row / n + x * 0.1F : 0.0F;
      side.at(x, row, 3) = data ? 1.0F : 0.0F;
    }
  const ImageRGBAF filled = device_fill(stage, side);
  for (int f : {4, 5}) {
    float lo = 1e9F, hi = -1e9F;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        lo = std::min(lo, filled.at(x, f * n + y, 0));
        hi = std::max(hi, filled.at(x, f * n + y, 0));
      }
    EXPECT_GE(lo, 1.0F) << f;
    EXPECT_LE(hi, 4.0F + 0.1F * n) << f;
    EXPECT_GT(hi - lo, 0.5F) << f;
  }
}

}  // namespace
}  // namespace probeless::envmap
