// accumulate_cpu (kernels/tracking/normal_equations_cpu.cpp), the tracker's CPU path, against
// accumulate_reference: the same sums on the synthetic room and on real TUM frames, with and
// without the rolling shutter, at every level (point counts that are not multiples of 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <vector>

#include "kernels/tracking/dense_tracker.hpp"
#include "kernels/tracking/frame_pyramid.hpp"
#include "kernels/tracking/keyframe.hpp"
#include "kernels/tracking/normal_equations.hpp"
#include "unit/tracking/iteration_params.hpp"
#include "unit/tracking/synthetic_scene.hpp"
#include "unit/tracking/tum_frames.hpp"

namespace probeless::tracking {
namespace {

constexpr std::array<float, 3> kNoReadout{};
constexpr std::array<float, 3> kReadout{0.004f, -0.022f, 0.006f};

void expect_same_sums(const FramePyramid& key_pyramid, const FramePyramid& current,
                      const DenseTrackerParams& params, const std::array<float, 3>& readout) {
  const Keyframe keyframe =
      make_keyframe(key_pyramid, Pose::identity(), params.max_points_per_level, readout);
  int odd_counts = 0;
  for (int level = 0; level < params.levels; ++level) {
    const IterationParams p =
        testing::iteration_params_near_motion(keyframe.cameras[std::size_t(level)], readout);
    const auto& points = keyframe.points[std::size_t(level)];
    odd_counts += points.size() % 4 != 0;
    const NormalSums ref = accumulate_reference(points, current.levels[std::size_t(level)], p);
    const NormalSums cpu = accumulate_cpu(points, current.levels[std::size_t(level)], p);
    ASSERT_GT(ref[kVisible], 50.0) << "level " << level;
    ASSERT_GT(ref[kGeoCount], 50.0) << "level " << level;
    ASSERT_GT(ref[kInliers], 0.0) << "level " << level;
    ASSERT_LT(ref[kInliers], ref[kVisible]) << "level " << level << ": no outliers to count";
    for (int k = 0; k < kSumCount; ++k) {
      // Same formulas in float, summed in another order: equal to float rounding of the
      // sums' size. Counts are exact (the same comparisons on the same floats).
      const double tolerance = k >= kPhotoCount && k <= kInliers && k != kPhotoWeightedSq &&
                                       k != kPhotoSq && k != kGeoWeightedSq && k != kGeoSq
                                   ? 0.0
                                   : 1e-4 * std::abs(ref[std::size_t(k)]) + 1e-5;
      EXPECT_NEAR(cpu[std::size_t(k)], ref[std::size_t(k)], tolerance)
          << "level " << level << " sum " << k;
    }
  }
  std::printf("levels with a point count not a multiple of 4: %d\n", odd_counts);
}

// fr1/rpy's frames 0 and 11 (the keyframe and a frame 0.37 s later) as pyramids.
void tum_pair(const DenseTrackerParams& params, FramePyramid& key_pyramid, FramePyramid& current) {
  const auto frames = testing::read_tum_frames(12);
  const auto camera = testing::tum_fr1_camera();
  const auto map = undistortion_map(camera, params.finest_level);
  build_pyramid_reference(frames[0].colour, frames[0].depth_mm, camera.intrinsics(), params, map,
                          key_pyramid);
  build_pyramid_reference(frames[11].colour, frames[11].depth_mm, camera.intrinsics(), params, map,
                          current);
}

TEST(AccumulateCpu, MatchesTheReferenceOnTheSyntheticRoom) {
  const PinholeIntrinsics camera{640, 480, 525.0, 525.0, 319.5, 239.5};
  const DenseTrackerParams params;
  const Pose moved{Eigen::Quaterniond(Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY())),
                   Eigen::Vector3d(0.02, -0.01, 0.01)};
  const auto key = testing::render_room(camera, Pose::identity());
  const auto cur = testing::render_room(camera, moved);
  FramePyramid key_pyramid, current;
  build_pyramid_reference(key.colour, key.depth_mm, camera, params, {}, key_pyramid);
  build_pyramid_reference(cur.colour, cur.depth_mm, camera, params, {}, current);
  expect_same_sums(key_pyramid, current, params, kNoReadout);
  expect_same_sums(key_pyramid, current, params, kReadout);
}

TEST(AccumulateCpu, MatchesTheReferenceOnTumFrames) {
  PROBELESS_REQUIRE_DATA(testing::kTumRpy);
  const DenseTrackerParams params;
  FramePyramid key_pyramid, current;
  tum_pair(params, key_pyramid, current);
  expect_same_sums(key_pyramid, current, params, kNoReadout);
  expect_same_sums(key_pyramid, current, params, kReadout);
}

// Not a test: the two paths' time per call on the finest level of real frames, interleaved
// (docs/performance.md; run with --gtest_also_run_disabled_tests).
TEST(AccumulateCpu, DISABLED_BenchAgainstTheReference) {
  PROBELESS_REQUIRE_DATA(testing::kTumRpy);
  const DenseTrackerParams params;
  FramePyramid key_pyramid, current;
  tum_pair(params, key_pyramid, current);
  const Keyframe keyframe =
      make_keyframe(key_pyramid, Pose::identity(), params.max_points_per_level, kReadout);
  IterationParams p{};
  const LevelCamera& c = keyframe.cameras[0];
  p.r[0] = p.r[4] = p.r[8] = 1.0f;
  p.fx = c.fx, p.fy = c.fy, p.cx = c.cx, p.cy = c.cy;
  p.inv_gain = 1.0f, p.inv_var_photo = 1.0f / 64.0f, p.inv_var_geo = 1.0f / 1e-4f, p.nu = 5.0f;
  p.photo_inlier = 20.0f, p.geo_inlier = 0.04f, p.min_depth = 0.15f;
  for (int i = 0; i < 3; ++i) p.readout_rotation[i] = kReadout[std::size_t(i)];
  std::vector<double> ref_us, cpu_us;
  double sink = 0;
  for (int round = 0; round < 200; ++round) {
    for (int which = 0; which < 2; ++which) {
      const auto t0 = std::chrono::steady_clock::now();
      const NormalSums s = which == 0
                               ? accumulate_reference(keyframe.points[0], current.levels[0], p)
                               : accumulate_cpu(keyframe.points[0], current.levels[0], p);
      const auto us =
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
      sink += s[kVisible];
      (which == 0 ? ref_us : cpu_us).push_back(us);
    }
  }
  std::nth_element(ref_us.begin(), ref_us.begin() + 100, ref_us.end());
  std::nth_element(cpu_us.begin(), cpu_us.begin() + 100, cpu_us.end());
  std::printf("%zu points: reference p50 %.1f us, cpu p50 %.1f us (%.2fx) [%g]\n",
              keyframe.points[0].size(), ref_us[100], cpu_us[100], ref_us[100] / cpu_us[100], sink);
}

}  // namespace
}  // namespace probeless::tracking
