// The device path of the dense tracker against its CPU reference: the pyramid, one
// iteration's normal equations, and whole tracks on real TUM frames.
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "kernels/tracking/dense_tracker.hpp"
#include "kernels/tracking/keyframe.hpp"
#include "kernels/tracking/normal_equations.hpp"
#include "kernels/tracking/tracking_device.hpp"
#include "support/cl_context.hpp"
#include "unit/tracking/iteration_params.hpp"
#include "unit/tracking/tum_frames.hpp"

namespace probeless::tracking {
namespace {

using testing::cl_context;

// Random colour and depth with holes and values outside the depth range.
std::pair<ImageRGB8, DepthImage> random_frame(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255), mm(0, 5000), hole(0, 9);
  ImageRGB8 colour(w, h);
  DepthImage depth(w, h);
  for (auto& v : colour.elements()) v = std::uint8_t(byte(rng));
  for (auto& d : depth.elements()) d = hole(rng) == 0 ? 0 : std::uint16_t(mm(rng));
  return {colour, depth};
}

void expect_same_pyramid(const FramePyramid& device, const FramePyramid& reference,
                         const std::string& what) {
  ASSERT_EQ(device.levels.size(), reference.levels.size());
  for (std::size_t l = 0; l < device.levels.size(); ++l) {
    const auto &d = device.levels[l], &r = reference.levels[l];
    ASSERT_EQ(d.intensity.width(), r.intensity.width()) << what << " level " << l;
    ASSERT_EQ(d.intensity.height(), r.intensity.height()) << what << " level " << l;
    float max_i = 0, max_d = 0;
    for (std::size_t i = 0; i < d.intensity.pixel_count(); ++i) {
      max_i = std::max(max_i, std::abs(d.intensity.data()[i] - r.intensity.data()[i]));
      max_d = std::max(max_d, std::abs(d.depth_m.data()[i] - r.depth_m.data()[i]));
    }
    EXPECT_LT(max_i, 1e-3f) << what << " level " << l;  // grey levels
    EXPECT_LT(max_d, 1e-5f) << what << " level " << l;  // metres
  }
}

// A rolling shutter's rotation over the readout (a fast pan, ~1.3 degrees), so both paths'
// corrections are compared too.
constexpr std::array<float, 3> kReadout{0.004f, -0.022f, 0.006f};

TEST(TrackingDevice, PyramidMatchesTheReference) {
  DenseTrackerParams params;
  const PinholeIntrinsics vga;
  const PinholeCamera distorted(vga, {0.26, -0.95, -0.005, 0.003, 1.16});
  TrackingDevice device(cl_context());
  unsigned seed = 1;
  // VGA, and odd sizes whose halves are rounded down at every level.
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{640, 480}, {643, 487}, {130, 98}}) {
    PinholeIntrinsics k = vga;
    k.width = w;
    k.height = h;
    const auto [colour, depth] = random_frame(w, h, seed++);
    for (int finest = 0; finest <= 1; ++finest) {
      params.finest_level = finest;
      params.levels = finest == 0 && w < 200 ? 3 : 4;
      if (w < 200 && finest == 1) params.levels = 2;
      for (const bool undistort : {false, true}) {
        const auto map =
            undistort && w == 640 ? undistortion_map(distorted, finest) : std::vector<float>{};
        FramePyramid reference, on_device;
        build_pyramid_reference(colour, depth, k, params, map, reference);
        device.set_undistortion(map);
        device.build_pyramid(colour, depth, k, params);
        device.download_pyramid(on_device);
        expect_same_pyramid(on_device, reference,
                            std::to_string(w) + "x" + std::to_string(h) + " finest " +
                                std::to_string(finest) + (map.empty() ? "" : " undistorted"));
      }
    }
  }
}

TEST(TrackingDevice, NormalEquationsMatchTheReferenceOnTumFrames) {
  PROBELESS_REQUIRE_DATA(testing::kTumRpy);
  const auto frames = testing::read_tum_frames(12);
  const DenseTrackerParams params;
  const auto camera = testing::tum_fr1_camera();
  const auto map = undistortion_map(camera, params.finest_level);
  TrackingDevice device(cl_context());
  FramePyramid key_pyramid, current;
  build_pyramid_reference(frames[0].colour, frames[0].depth_mm, camera.intrinsics(), params, map,
                          key_pyramid);
  Keyframe keyframe =
      make_keyframe(key_pyramid, Pose::identity(), params.max_points_per_level, kReadout);
  device.upload_points(keyframe);
  build_pyramid_reference(frames[11].colour, frames[11].depth_mm, camera.intrinsics(), params, map,
                          current);
  device.set_undistortion(map);
  device.build_pyramid(frames[11].colour, frames[11].depth_mm, camera.intrinsics(), params);
  for (int level = 0; level < params.levels; ++level) {
    const IterationParams p =
        testing::iteration_params_near_motion(keyframe.cameras[std::size_t(level)], kReadout);
    const NormalSums ref = accumulate_reference(keyframe.points[std::size_t(level)],
                                                current.levels[std::size_t(level)], p);
    const NormalSums dev = device.accumulate(keyframe, level, p);
    ASSERT_GT(ref[kVisible], 100.0) << "level " << level;
    ASSERT_GT(ref[kGeoCount], 100.0) << "level " << level;
    for (int k = 0; k < kSumCount; ++k) {
      // Counts agree but for points whose projection lands on a pixel boundary in one of the
      // two float paths; sums to float precision of their size.
      const double tolerance = 1e-3 * std::abs(ref[std::size_t(k)]) + 2e-3 * std::abs(ref[kG]) +
                               (k >= kPhotoCount ? 2.0 : 1e-6 * std::abs(ref[kH]));
      EXPECT_NEAR(dev[std::size_t(k)], ref[std::size_t(k)], tolerance)
          << "level " << level << " sum " << k;
    }
  }
}

// The device's point selection and precomputation against keyframe.cpp's, on real frames.
TEST(TrackingDevice, KeyframePointsMatchTheReferenceOnTumFrames) {
  PROBELESS_REQUIRE_DATA(testing::kTumRpy);
  const auto frames = testing::read_tum_frames(1);
  const DenseTrackerParams params;
  const auto camera = testing::tum_fr1_camera();
  const auto map = undistortion_map(camera, params.finest_level);
  FramePyramid pyramid;
  build_pyramid_reference(frames[0].colour, frames[0].depth_mm, camera.intrinsics(), params, map,
                          pyramid);
  const Keyframe reference =
      make_keyframe(pyramid, Pose::identity(), params.max_points_per_level, kReadout);
  TrackingDevice device(cl_context());
  device.set_undistortion(map);
  device.build_pyramid(frames[0].colour, frames[0].depth_mm, camera.intrinsics(), params);
  const Keyframe on_device =
      device.make_keyframe(Pose::identity(), params.max_points_per_level, kReadout);
  ASSERT_EQ(on_device.device_points.size(), on_device.points.size());  // uploaded
  for (std::size_t l = 0; l < reference.points.size(); ++l) {
    const auto &a = reference.points[l], &b = on_device.points[l];
    ASSERT_GT(a.size(), 200u) << "level " << l;
    // The pyramids differ by float rounding, which may flip a near tie of gradients: allow a
    // few points chosen differently, compare the rest value by value.
    ASSERT_NEAR(double(b.size()), double(a.size()), 2.0) << "level " << l;
    std::size_t same = 0, normals = 0;
    for (std::size_t i = 0, j = 0; i < a.size() && j < b.size(); ++i, ++j) {
      const float* pa = &a[i].x;
      const float* pb = &b[j].x;
      if (std::abs(pa[0] - pb[0]) > 1e-4f || std::abs(pa[1] - pb[1]) > 1e-4f) continue;
      ++same;
      normals += a[i].has_normal > 0.0f;
      // The photometric Jacobian carries the pyramids' rounding through a difference of
      // neighbours: compared relative to its largest component.
      float j_scale = 0.0f;
      for (int k = 8; k < 14; ++k) j_scale = std::max(j_scale, std::abs(pa[k]));
      for (int k = 0; k < 24; ++k) {
        const float scale = k >= 8 && k < 14 ? j_scale : std::abs(pa[k]);
        EXPECT_NEAR(pb[k], pa[k], 1e-3f * (1.0f + scale))
            << "level " << l << " point " << i << " field " << k;
      }
    }
    EXPECT_GT(double(same), 0.99 * double(a.size())) << "level " << l;
    EXPECT_GT(normals, same / 2) << "level " << l;
  }
}

TEST(DenseTrackerDevice, TracksTumFramesLikeTheReference) {
  PROBELESS_REQUIRE_DATA(testing::kTumRpy);
  const auto frames = testing::read_tum_frames(40);
  DenseTracker cpu(nullptr, testing::tum_fr1_camera(), testing::tum_params());
  DenseTracker gpu(&cl_context(), testing::tum_fr1_camera(), testing::tum_params());
  EXPECT_FALSE(cpu.uses_device());
  EXPECT_TRUE(gpu.uses_device());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto& f = frames[i];
    const TrackResult a = cpu.track(f.colour, f.depth_mm, f.timestamp_ns);
    const TrackResult b = gpu.track(f.colour, f.depth_mm, f.timestamp_ns);
    ASSERT_EQ(a.state, TrackingState::Tracking) << "frame " << i;
    ASSERT_EQ(b.state, TrackingState::Tracking) << "frame " << i;
    EXPECT_LT((a.T_world_camera.translation - b.T_world_camera.translation).norm(), 0.002)
        << "frame " << i;
    EXPECT_LT(a.T_world_camera.rotation.angularDistance(b.T_world_camera.rotation), 0.002)
        << "frame " << i;
    EXPECT_NEAR(a.inlier_fraction, b.inlier_fraction, 0.02) << "frame " << i;
  }
}

TEST(DenseTrackerDevice, TracksFr1RpyWithoutLossBelowTheAteBound) {
  PROBELESS_REQUIRE_DATA(testing::kTumRpy);
  const auto frames = testing::read_tum_frames();
  DenseTracker tracker(&cl_context(), testing::tum_fr1_camera(), testing::tum_params());
  const auto run = testing::run_tum(tracker, frames);
  testing::print_tum_run("OpenCL device", frames.size(), run);
  EXPECT_EQ(run.lost, 0);
  EXPECT_LT(run.ate_m, 0.0135);  // as the CPU reference's test (tests/unit/tracking)
}

}  // namespace
}  // namespace probeless::tracking
