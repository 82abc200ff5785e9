// The tracker on 150 real frames of TUM fr1/rpy (Kinect v1, motion capture ground truth).
#include <gtest/gtest.h>

#include <algorithm>

#include "kernels/tracking/dense_tracker.hpp"
#include "unit/tracking/tum_frames.hpp"

namespace probeless::tracking {
namespace {

// The bar of issue #17 is half the best OpenCV 4.6 odometry on the same frames: RgbdICP gave
// 0.0396 m here (frame to frame, default parameters, no distortion; docs/tracking.md), so
// 0.0198 m. The tracker measured 0.0186 m, 0.0167 m once it turned back to kept keyframes and
// 0.0125 m with the Kinect's rolling shutter modelled (0.0120 m once the first keyframe, taken
// while turning, was unsheared too); the bound is 0.0125 m with a margin of 8%.
constexpr double kAteBoundM = 0.0135;

TEST(DenseTrackerTum, TracksFr1RpyWithoutLossBelowTheAteBound) {
  PROBELESS_REQUIRE_DATA(testing::kTumRpy);
  const auto frames = testing::read_tum_frames();
  ASSERT_EQ(frames.size(), 150u);
  DenseTracker tracker(nullptr, testing::tum_fr1_camera(), testing::tum_params());
  const auto run = testing::run_tum(tracker, frames);
  testing::print_tum_run("CPU path", frames.size(), run);
  EXPECT_EQ(run.lost, 0);
  EXPECT_LT(run.ate_m, kAteBoundM);
  EXPECT_GT(run.keyframes, 1);  // rpy turns by tens of degrees: keyframes must switch
}

// Real frames for the loss test: the view turned upside down (same sensor, same statistics,
// another view) is lost, and the tracker relocalises when the real view returns.
TEST(DenseTrackerTum, LosesAnUnrelatedViewAndRelocalisesOnTheNextRealOne) {
  PROBELESS_REQUIRE_DATA(testing::kTumRpy);
  const auto frames = testing::read_tum_frames(6);
  DenseTracker tracker(nullptr, testing::tum_fr1_camera());
  for (int i = 0; i < 3; ++i)
    ASSERT_EQ(
        tracker.track(frames[std::size_t(i)].colour, frames[std::size_t(i)].depth_mm, 0).state,
        TrackingState::Tracking);
  auto upside_down = frames[3];
  std::reverse(upside_down.depth_mm.elements().begin(), upside_down.depth_mm.elements().end());
  const auto c = upside_down.colour.elements();
  for (std::size_t a = 0, b = c.size() - 3; a < b; a += 3, b -= 3)
    for (int k = 0; k < 3; ++k) std::swap(c[a + std::size_t(k)], c[b + std::size_t(k)]);
  const TrackResult lost = tracker.track(upside_down.colour, upside_down.depth_mm, 0);
  std::printf("upside-down frame: inliers %.3f, visible %.3f, residual %.1f\n",
              lost.inlier_fraction, lost.visible_fraction, lost.residual_rms);
  EXPECT_EQ(lost.state, TrackingState::Lost);
  const TrackResult back = tracker.track(frames[4].colour, frames[4].depth_mm, 0);
  EXPECT_EQ(back.state, TrackingState::Tracking);
  EXPECT_TRUE(back.relocalised);
  ASSERT_TRUE(frames[4].truth && frames[0].truth);
  const Pose truth = frames[0].truth->inverse() * *frames[4].truth;
  EXPECT_LT((back.T_world_camera.translation - truth.translation).norm(), 0.01);
}

}  // namespace
}  // namespace probeless::tracking
