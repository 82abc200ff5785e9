// The tracker on 150 real frames of TUM fr1/rpy (Kinect v1, motion capture ground truth).
#include <gtest/gtest.h>

#include <algorithm>

#include "kernels/tracking/dense_tracker.hpp"
#include "unit/tracking/tum_frames.hpp"

namespace probeless::tracking {
namespace {

TEST(DenseTrackerTum, TracksFr1RpyWithinTheAteBound) {
  PROBELESS_REQUIRE_DATA(testing::kTumRpy);
  const auto frames = testing::read_tum_frames();
  ASSERT_GE(frames.size(), 100u);
  DenseTracker tracker(nullptr, testing::tum_fr1_camera());
  std::vector<Eigen::Vector3d> estimate, truth;
  std::vector<double> ms;
  int lost = 0, keyframes = 0;
  double min_inliers = 1.0;
  for (const auto& f : frames) {
    const auto t0 = std::chrono::steady_clock::now();
    const TrackResult r = tracker.track(f.colour, f.depth_mm, f.timestamp_ns);
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if (r.state != TrackingState::Tracking) {
      ++lost;
      continue;
    }
    keyframes += r.new_keyframe;
    min_inliers = std::min(min_inliers, r.inlier_fraction);
    if (!f.truth) continue;
    estimate.push_back(r.T_world_camera.translation);
    truth.push_back(f.truth->translation);
  }
  std::sort(ms.begin(), ms.end());
  const double ate = testing::ate_rmse(estimate, truth);
  std::printf(
      "fr1/rpy %zu frames: ATE %.4f m, lost %d, keyframes %d, min inliers %.3f, "
      "p50 %.2f ms, p99 %.2f ms (CPU reference)\n",
      frames.size(), ate, lost, keyframes, min_inliers, ms[ms.size() / 2],
      ms[ms.size() * 99 / 100]);
  EXPECT_EQ(lost, 0);
  EXPECT_LT(ate, 0.03);
}

}  // namespace
}  // namespace probeless::tracking
