// The sim's near occluder (near_occluder=1): a hand in front of the colour camera, nearer than
// the depth sensor's range, so the noise model gives it no depth; off, the frames are the
// ones every other test and measurement was taken with.
#include <gtest/gtest.h>

#include "core/depth_noise.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "tests/unit/sim/sim_first_frame.hpp"

namespace probeless::sim {
namespace {

TEST(SimNearOccluder, OptionParses) {
  EXPECT_FALSE(parse_sim_options("").near_occluder);
  EXPECT_TRUE(parse_sim_options("near_occluder=1").near_occluder);
  try {
    parse_sim_options("near_occluder=2");
    ADD_FAILURE() << "near_occluder=2 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'near_occluder'"), std::string::npos) << e.what();
  }
}

TEST(SimNearOccluder, TheHandIsNearerThanTheSensorsRangeAndHasNoDepth) {
  // t = 1.5 s: the hand over the middle of the tabletop view.
  const RgbdFrame f =
      first_frame("realtime=0,trajectory=tabletop,near_occluder=1,start=1.5,frames=1");
  const auto min_mm = static_cast<int>(KinectNoiseParams{}.min_depth_m * 1000);
  const auto is_near = [&](int x, int y) { return f.truth->clean_depth.at(x, y) < min_mm; };
  int near = 0, centre_near = 0, inside = 0;
  for (int y = 0; y < f.colour.height(); ++y)
    for (int x = 0; x < f.colour.width(); ++x) {
      if (!is_near(x, y)) continue;
      ++near;
      centre_near += std::abs(x - 320) < 40 && std::abs(y - 240) < 40;
      ASSERT_EQ(f.truth->occluder_mask.at(x, y), 255) << "only the hand is that near";
      ASSERT_GT(f.truth->clean_depth.at(x, y), 200) << "the hand stays 0.25 m or more away";
      // The sensor model's dots fill up to 3 px around them, so the background's reach over
      // the hand's edge: inside it there is no depth at all.
      bool interior = x >= 3 && y >= 3 && x + 3 < f.colour.width() && y + 3 < f.colour.height();
      for (int v = -3; v <= 3 && interior; ++v)
        for (int u = -3; u <= 3 && interior; ++u) interior = is_near(x + u, y + v);
      if (!interior) continue;
      ++inside;
      ASSERT_EQ(f.depth.at(x, y), 0) << "depth on the near hand at (" << x << ", " << y << ")";
    }
  EXPECT_GT(inside, near / 2);
  EXPECT_GT(near, 10000) << "a hand at 0.3 m covers a good part of the view";
  EXPECT_GT(centre_near, 3000) << "over the middle of the view, where the objects are";
}

TEST(SimNearOccluder, FramesWithTheHandOutOfViewChangeOnlyInTheMirrorBall) {
  // t = 4 s: the hand rests out of view (and out of the last frames' exposure metering); only
  // the table's mirror ball, which reflects it, can show it. (Off, the option changes nothing:
  // the occluder is the arm's three capsules as before.)
  const std::string spec = "realtime=0,trajectory=tabletop,start=4,frames=1";
  const RgbdFrame with = first_frame(spec + ",near_occluder=1"), without = first_frame(spec);
  ASSERT_EQ(with.colour.width(), without.colour.width());
  int differ = 0;
  for (int y = 0; y < with.colour.height(); ++y)
    for (int x = 0; x < with.colour.width(); ++x) {
      ASSERT_EQ(with.depth.at(x, y), without.depth.at(x, y)) << x << ", " << y;
      bool same = true;
      for (int c = 0; c < 3; ++c)
        same = same && with.colour.at(x, y, c) == without.colour.at(x, y, c);
      if (same) continue;
      ++differ;
      EXPECT_EQ(with.depth.at(x, y), 0) << "(" << x << ", " << y << ") is not on the mirror ball";
    }
  EXPECT_LT(differ, 100);
}

}  // namespace
}  // namespace probeless::sim
