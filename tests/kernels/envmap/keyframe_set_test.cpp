#include "kernels/envmap/keyframe_set.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

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
  KeyframeConfig none;
  none.max_keyframes = 0;
  EXPECT_THROW(KeyframeSet(cl_context(), none), std::invalid_argument);
}

std::vector<int> ids_of(const KeyframeSet& set) {
  std::vector<int> ids;
  for (const auto& k : set.keyframes()) ids.push_back(k->id);
  return ids;
}

// Issue #20's soak: a new keyframe every 0.5 m and none dropped grew the service by 3.8 GB an
// hour. A long walk (200 captures 0.6 m apart, each a new keyframe, wandering in the plane so
// that distances differ) holds the set at the cap, and each capture drops the keyframe that
// was farthest from it.
TEST(KeyframeSet, LongWalkHoldsTheCapDroppingTheFarthest) {
  auto& ctx = cl_context();
  KeyframeConfig config;
  config.face_size = 4;
  config.max_keyframes = 16;
  KeyframeSet set(ctx, config);
  Eigen::Vector3d p(0, 0, 1.5);
  double heading = 0;
  int made = 0;
  for (int i = 0; i < 200; ++i) {
    heading += 0.9 * std::sin(0.37 * i);  // a meander, reproducible
    p += 0.6 * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0);
    // What the rule should drop: of those held, the one farthest from p (no ties here).
    int farthest = -1;
    double farthest_d = -1;
    for (const auto& k : set.keyframes())
      if ((k->position - p).norm() > farthest_d) {
        farthest_d = (k->position - p).norm();
        farthest = k->id;
      }
    const bool full = static_cast<int>(set.keyframes().size()) == config.max_keyframes;
    const bool new_one = !set.nearest(p) || (set.nearest(p)->position - p).norm() > 0.5;
    Keyframe& k = set.for_capture(p);
    ASSERT_LE(static_cast<int>(set.keyframes().size()), config.max_keyframes) << "capture " << i;
    ASSERT_EQ(set.active_id(), k.id);
    if (new_one) {
      ++made;
      ASSERT_EQ(k.position, p);
      if (full) {
        ASSERT_EQ(set.find(farthest), nullptr) << "capture " << i << " kept the farthest";
      }
    }
  }
  EXPECT_EQ(static_cast<int>(set.keyframes().size()), config.max_keyframes);
  EXPECT_GT(made, 80);  // the meander comes back near old places now and then
  EXPECT_EQ(set.dropped(), static_cast<std::uint64_t>(made - config.max_keyframes));
  EXPECT_EQ(set.dropped() + set.keyframes().size(),
            static_cast<std::size_t>(set.keyframes().back()->id + 1));
  // Ids are never reused: a cache keyed by id cannot hand a dropped keyframe's state to another.
  std::vector<int> ids = ids_of(set);
  EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
  EXPECT_EQ(std::adjacent_find(ids.begin(), ids.end()), ids.end());
  for (const auto& kept : set.keyframes()) EXPECT_EQ(set.find(kept->id), kept.get());
}

// Equally far keyframes: the one a capture chose least recently goes.
TEST(KeyframeSet, OfEquallyFarDropsTheLeastRecentlyUpdated) {
  auto& ctx = cl_context();
  KeyframeConfig config;
  config.face_size = 4;
  config.max_keyframes = 3;
  KeyframeSet set(ctx, config);
  const int a = set.for_capture({0, 0, 1}).id;
  const int b = set.for_capture({2, 0, 1}).id;
  const int c = set.for_capture({0, 2, 1}).id;
  EXPECT_EQ(set.for_capture({2.1, 0, 1}).id, b);  // updated again, then a
  EXPECT_EQ(set.for_capture({0.1, 0, 1}).id, a);
  // (1, 1) is sqrt(2) from all three: c was chosen least recently.
  const int d = set.for_capture({1, 1, 1}).id;
  EXPECT_EQ(ids_of(set), (std::vector<int>{a, b, d}));
  EXPECT_EQ(set.find(c), nullptr);
  // Not a tie: from (3, 0), a (3 m) is farther than d (2.2 m) and b (1 m).
  const int e = set.for_capture({3, 0, 1}).id;
  EXPECT_EQ(ids_of(set), (std::vector<int>{b, d, e}));
  EXPECT_EQ(set.dropped(), 2U);
}

// A cap of one: the new keyframe's seed (the keyframe it replaces) is read before it goes, and
// the active keyframe dropped leaves no dangling active id.
TEST(KeyframeSet, CapOfOneSeedsFromTheKeyframeItDrops) {
  auto& ctx = cl_context();
  KeyframeConfig config;
  config.face_size = 8;
  config.max_keyframes = 1;
  KeyframeSet set(ctx, config);
  Keyframe& first = set.for_capture({0, 0, 1});
  ImageRGBAF t = make_texels(8);
  for (int y = 0; y < t.height(); ++y)
    for (int x = 0; x < t.width(); ++x) {
      for (int c = 0; c < 3; ++c) t.at(x, y, c) = static_cast<float>(1 + x + 10 * y + c);
      t.at(x, y, 3) = 1.0F;
    }
  first.texels.upload(ctx.queue(), t);
  Keyframe& second = set.for_capture({0.6, 0, 1});
  ASSERT_EQ(set.keyframes().size(), 1U);
  EXPECT_EQ(second.id, 1);
  EXPECT_EQ(set.find(0), nullptr);
  EXPECT_EQ(set.active_id(), 1);
  const ImageRGBAF s = second.texels.download(ctx.queue());
  for (int y = 0; y < s.height(); ++y)
    for (int x = 0; x < s.width(); ++x) {
      for (int c = 0; c < 3; ++c) ASSERT_EQ(s.at(x, y, c), t.at(x, y, c));
      ASSERT_EQ(s.at(x, y, 3), 0.0F);
    }
}

}  // namespace
}  // namespace probeless::envmap
