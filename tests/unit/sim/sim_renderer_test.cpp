#include "drivers/sim/sim_renderer.hpp"

#include <gtest/gtest.h>

#include "drivers/sim/sim_world.hpp"

namespace probeless::sim {
namespace {

// The colour camera of the static rig, as make_sim_rig places it.
Pose static_camera(const SimWorld& world) {
  Eigen::Matrix3d r;
  r << Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY();
  Pose rgb_in_rig;
  rgb_in_rig.rotation = Eigen::Quaterniond(r);
  return world.rig_pose(TrajectoryKind::Static, 0) * rgb_in_rig;
}

SimRenderer pinhole(const std::shared_ptr<const SimWorld>& world) {
  return SimRenderer(world, 640, 480, 525, 525, 319.5, 239.5, nullptr);
}

TEST(SimRenderer, StillViewCastsOnlyWhatTheArmTouches) {
  const auto world = std::make_shared<const SimWorld>(1);
  const Pose camera = static_camera(*world);
  constexpr int kTiles = 40 * 30;

  SimRenderer cached = pinhole(world);
  cached.render(camera, 1, nullptr, true);
  EXPECT_EQ(cached.tiles_cast(), kTiles);
  const ImageRGBF still = cached.radiance();
  cached.render(camera, 1, nullptr, true);
  EXPECT_EQ(cached.tiles_cast(), 0) << "nothing moved";
  EXPECT_TRUE(cached.radiance() == still);

  // The arm in view: only its tiles are cast, and the picture is the one a fresh renderer
  // makes; when it leaves, its tiles are cast once more to clear it.
  const Occluder arm = world->occluder(3.25, camera.translation);  // mid-sweep
  cached.render(camera, 1, &arm, true);
  EXPECT_GT(cached.tiles_cast(), 0);
  EXPECT_LT(cached.tiles_cast(), kTiles / 2);
  SimRenderer fresh = pinhole(world);
  fresh.render(camera, 1, &arm, true);
  EXPECT_TRUE(cached.radiance() == fresh.radiance());
  EXPECT_TRUE(cached.depth() == fresh.depth());
  EXPECT_TRUE(cached.flags() == fresh.flags());
  cached.render(camera, 1, nullptr, true);
  EXPECT_GT(cached.tiles_cast(), 0);
  EXPECT_TRUE(cached.radiance() == still);

  cached.render(camera, 0, nullptr, true);
  EXPECT_EQ(cached.tiles_cast(), kTiles) << "a lamp switched: everything again";
}

TEST(SimRenderer, DepthIsAlongTheOpticalAxis) {
  const auto world = std::make_shared<const SimWorld>(1);
  const Pose camera = static_camera(*world);
  SimRenderer r = pinhole(world);
  r.render(camera, 1, nullptr, true);
  // The back wall (y = 2.5) faces the static camera: the same depth across the image.
  const double wall = 2.5 - camera.translation.y();
  EXPECT_NEAR(r.depth().at(320, 60), wall, 1e-4);
  EXPECT_NEAR(r.depth().at(40, 100), wall, 1e-4);
  EXPECT_EQ(r.flags().at(320, 60), 0);
}

}  // namespace
}  // namespace probeless::sim
