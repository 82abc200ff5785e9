#include "kernels/envmap/keyframe_set.hpp"

#include <gtest/gtest.h>

#include "support/cl_context.hpp"

namespace probeless::envmap {
namespace {

using probeless::testing::cl_context;

TEST(KeyframeSet, NewKeyframeBeyondTheThresholdSeededUnobserved) {
  auto& ctx = cl_context();
  KeyframeConfig config;
  config.face_size = 8;
  config.new_keyframe_distance_m = 0.5;
  KeyframeSet set(ctx, config);
  EXPECT_EQ(set.nearest({0, 0, 0}), nullptr);

  Keyframe& first = set.for_capture({0, 0, 1});
  EXPECT_EQ(first.id, 0);
  ImageRGBAF t = first.texels.download(ctx.queue());
  for (float v : t.elements()) ASSERT_EQ(v, 0.0F);  // the first starts empty
  for (int y = 0; y < t.height(); ++y)
    for (int x = 0; x < t.width(); ++x) {
      for (int c = 0; c < 3; ++c) t.at(x, y, c) = static_cast<float>(x + 10 * y + c);
      t.at(x, y, 3) = 0.25F;
    }
  first.texels.upload(ctx.queue(), t);

  EXPECT_EQ(set.for_capture({0.3, 0, 1}).id, 0);  // within 0.5 m
  EXPECT_EQ(set.keyframes().size(), 1U);
  Keyframe& second = set.for_capture({0.6, 0, 1});
  EXPECT_EQ(second.id, 1);
  EXPECT_EQ(second.position, Eigen::Vector3d(0.6, 0, 1));
  const ImageRGBAF s = second.texels.download(ctx.queue());
  for (int y = 0; y < s.height(); ++y)
    for (int x = 0; x < s.width(); ++x) {
      for (int c = 0; c < 3; ++c) ASSERT_EQ(s.at(x, y, c), t.at(x, y, c));
      ASSERT_EQ(s.at(x, y, 3), 0.0F);  // seeded: the next observation replaces
    }
  EXPECT_EQ(set.active_id(), 1);

  // Back near the start: the old keyframe again, not a new one.
  EXPECT_EQ(set.for_capture({0.1, 0, 1}).id, 0);
  EXPECT_EQ(set.keyframes().size(), 2U);
  EXPECT_EQ(set.active_id(), 0);
  EXPECT_EQ(set.nearest({0.5, 0, 1})->id, 1);
  EXPECT_EQ(set.nearest({0.2, 0, 1})->id, 0);
  // Its texels were left alone.
  EXPECT_EQ(set.keyframes()[0]->texels.download(ctx.queue()), t);
  // A third, seeded from the nearest (the second), beyond both.
  EXPECT_EQ(set.for_capture({1.2, 0, 1}).id, 2);
}

TEST(KeyframeSet, RejectsBadConfig) {
  KeyframeConfig bad;
  bad.new_keyframe_distance_m = 0;
  EXPECT_THROW(KeyframeSet(cl_context(), bad), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::envmap
