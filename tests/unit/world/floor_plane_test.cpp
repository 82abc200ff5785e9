// `[world] anchor = "floor"`: RANSAC on synthetic depth of a room with a table, a wall and
// clutter, with Kinect-class noise (app/world/floor_plane).
#include "app/world/floor_plane.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace probeless::world {
namespace {

constexpr double kDeg = M_PI / 180;

struct Box {
  Eigen::Vector3d lo, hi;
};

// A camera `height` m above the floor (z = 0, world z up), looking along +y pitched down by
// `pitch_deg` and rolled by `roll_deg`; returns T_world_camera (OpenCV camera axes).
Pose camera_pose(double height, double pitch_deg, double roll_deg = 0) {
  Eigen::Matrix3d level;  // camera x = world x, camera y = -world z, camera z = world y
  level << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  Pose p;
  p.rotation = Eigen::Quaterniond(level) *
               Eigen::AngleAxisd(-pitch_deg * kDeg, Eigen::Vector3d::UnitX()) *
               Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitZ());
  p.translation = Eigen::Vector3d(0, 0, height);
  return p;
}

double hit_box(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Box& b) {
  double t0 = 0, t1 = 1e9;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12) {
      if (o[a] < b.lo[a] || o[a] > b.hi[a]) return 1e9;
      continue;
    }
    double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 && t0 > 0 ? t0 : 1e9;
}

// Depth in mm of the floor plus the boxes, with noise sigma = 1.4 mm z^2 (Khoshelham &
// Elberink 2012) and 2 % of pixels dropped.
DepthImage render(const PinholeIntrinsics& k, const Pose& T_world_camera,
                  const std::vector<Box>& boxes, std::uint64_t seed = 7) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  DepthImage depth(k.width, k.height);
  const Eigen::Vector3d o = T_world_camera.translation;
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) {
      const Eigen::Vector3d ray((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1);  // z = 1 in camera
      const Eigen::Vector3d d = T_world_camera.rotation * ray;
      double t = d.z() < -1e-9 ? -o.z() / d.z() : 1e9;
      for (const Box& b : boxes) t = std::min(t, hit_box(o, d, b));
      if (t > 5 || u(rng) < 0.02) continue;  // t is the camera depth: ray has z = 1
      const double z = t + noise(rng) * 1.4e-3 * t * t;
      depth.at(x, y) = static_cast<std::uint16_t>(std::lround(z * 1000));
    }
  return depth;
}

const std::vector<Box> kRoom = {
    {{-0.75, 1.2, 0.72}, {0.75, 2.0, 0.75}},  // a table top
    {{-3, 3.5, 0}, {3, 3.6, 2.7}},            // the back wall
    {{-0.6, 1.4, 0.75}, {-0.4, 1.6, 0.95}},   // a box on the table
    {{0.8, 1.0, 0}, {1.2, 1.4, 0.6}},         // a crate on the floor
};

TEST(FloorPlane, FindsTheFloorUnderClutterWithinHalfADegree) {
  const PinholeIntrinsics k;
  for (const double pitch : {20.0, 30.0, 40.0}) {
    const Pose T_world_camera = camera_pose(1.5, pitch);
    const auto floor = find_floor(render(k, T_world_camera, kRoom), k);
    ASSERT_TRUE(floor) << pitch;
    const Eigen::Vector3d up_in_camera =
        T_world_camera.rotation.inverse() * Eigen::Vector3d::UnitZ();
    const double err_deg = std::acos(std::min(1.0, floor->normal.dot(up_in_camera))) / kDeg;
    EXPECT_LT(err_deg, 0.5) << "pitch " << pitch;
    std::cout << "pitch " << pitch << ": normal off by " << err_deg << " deg, " << floor->inliers
              << " inliers\n";
    EXPECT_NEAR(floor->offset, 1.5, 0.01) << "the camera's height, pitch " << pitch;
    // The world it gives: z up, origin on the floor where the optical axis meets it.
    const Pose T_world_floor = T_world_camera * floor->T_camera_floor;
    EXPECT_LT(
        std::acos(std::min(1.0, (T_world_floor.rotation * Eigen::Vector3d::UnitZ()).z())) / kDeg,
        0.5);
    EXPECT_NEAR(T_world_floor.translation.z(), 0, 0.01);
    EXPECT_NEAR(T_world_floor.translation.x(), 0, 0.02);
    if (pitch >= 25) {  // the axis meets the floor within range: the origin is on it
      EXPECT_NEAR(T_world_floor.translation.y(), 1.5 / std::tan(pitch * kDeg), 0.05) << pitch;
    }
  }
}

TEST(FloorPlane, TheLargestHorizontalPlaneWinsAndATiltedOneIsRefused) {
  const PinholeIntrinsics k;
  // Close over a big table: its top fills most of the view, the floor shows at the edges.
  const std::vector<Box> big_table = {{{-2, 0.2, 0.72}, {2, 3, 0.75}}};
  const auto floor = find_floor(render(k, camera_pose(1.2, 35), big_table), k);
  ASSERT_TRUE(floor);
  EXPECT_NEAR(floor->offset, 1.2 - 0.75, 0.01);
  // Rolled by 60 degrees, no plane is within 45 degrees of the camera's down direction.
  EXPECT_FALSE(find_floor(render(k, camera_pose(1.5, 25, 60), kRoom), k));
  FloorParams wide;
  wide.max_tilt_deg = 80;
  EXPECT_TRUE(find_floor(render(k, camera_pose(1.5, 25, 60), kRoom), k, wide));
}

TEST(FloorPlane, NoPlaneInAnEmptyOrVerticalViewAndSizesAreChecked) {
  const PinholeIntrinsics k;
  EXPECT_FALSE(find_floor(DepthImage(k.width, k.height), k));
  // Facing a wall from 1 m, level: no horizontal plane in view.
  const std::vector<Box> wall = {{{-5, 1, -5}, {5, 1.1, 5}}};
  EXPECT_FALSE(find_floor(render(k, camera_pose(1.5, 0), wall), k));
  EXPECT_THROW(find_floor(DepthImage(320, 240), k), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::world
