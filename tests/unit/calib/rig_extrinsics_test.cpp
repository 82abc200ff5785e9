// The rig extrinsics solver on synthetic board corners with known truth (issue #18 item 1's
// bar: within 2 mm and 0.2 degrees), a wrong view left out, and its clear errors.
#include "lab/calib/rig_extrinsics.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include "core/camera/kannala_brandt.hpp"
#include "core/camera/pinhole.hpp"
#include "lab/calib/intrinsics.hpp"
#include "unit/calib/synthetic_board.hpp"

namespace probeless::calib {
namespace {
using namespace probeless::calib::testing;

struct SyntheticRig {
  PinholeCamera rgb{PinholeIntrinsics{640, 480, 525, 525, 319.5, 239.5},
                    BrownDistortion{0.05, -0.1, 0.001, -0.001, 0}};
  KannalaBrandtCamera fisheye{
      KannalaBrandtParams{800, 800, 229, 229.5, 399.5, 401, {0.02, -0.01, 0.003, 0}, 1.745}};
  Pose T_rgb_fisheye;  // the fisheye looks up (along the colour camera's -y)
  SyntheticRig() {
    T_rgb_fisheye.rotation = rotation_deg(90, 0, 0) * rotation_deg(1.5, -2, 3);
    T_rgb_fisheye.translation = {0.03, -0.06, 0.012};
  }
};

Pose jittered(const Pose& p, double deg, double m, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Pose out = p;
  out.rotation = p.rotation * rotation_deg(deg * u(rng), deg * u(rng), deg * u(rng));
  out.translation += m * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return out;
}

// Views in which both cameras see the whole board, with per-camera board poses jittered as a
// per-camera calibration would leave them.
std::vector<StereoView> stereo_views(const SyntheticRig& rig, int count, double noise_px,
                                     std::mt19937& rng) {
  std::uniform_real_distribution<double> x(-0.15, 0.15), y(-0.25, -0.12), z(0.6, 0.9),
      tilt(-25, 25), spin(-30, 30);
  const Pose T_fisheye_rgb = rig.T_rgb_fisheye.inverse();
  std::vector<StereoView> views;
  while (static_cast<int>(views.size()) < count) {
    const Pose T_rgb_board = board_pose({x(rng), y(rng), z(rng)}, tilt(rng), tilt(rng), spin(rng));
    const Pose T_fisheye_board = T_fisheye_rgb * T_rgb_board;
    auto rgb_px = project_board(rig.rgb, T_rgb_board, noise_px, rng);
    auto fisheye_px = project_board(rig.fisheye, T_fisheye_board, noise_px, rng);
    if (rgb_px.empty() || fisheye_px.empty()) continue;
    views.push_back({"view" + std::to_string(views.size()), board_corners(), rgb_px,
                     board_corners(), fisheye_px, jittered(T_rgb_board, 1.5, 0.01, rng),
                     jittered(T_fisheye_board, 1.5, 0.01, rng)});
  }
  return views;
}

double rotation_error_deg(const Pose& a, const Pose& b) {
  return a.rotation.angularDistance(b.rotation) * 180.0 / std::numbers::pi;
}

TEST(RigExtrinsics, RecoversTheFisheyePoseWithin2MmAnd0_2Degrees) {
  const SyntheticRig rig;
  std::mt19937 rng(7);
  auto views = stereo_views(rig, 15, 0.3, rng);
  // One view whose fisheye board pose is badly wrong (a flipped corner order would do this):
  // the robust initial estimate must leave it out.
  views[4].T_fisheye_board = jittered(views[4].T_fisheye_board, 40, 0.1, rng);
  const RigExtrinsics ext = solve_rig_extrinsics(rig.rgb, rig.fisheye, views);

  const double t_err = (ext.T_rgb_fisheye.translation - rig.T_rgb_fisheye.translation).norm();
  const double r_err = rotation_error_deg(ext.T_rgb_fisheye, rig.T_rgb_fisheye);
  std::cout << "T_rgb_fisheye error: " << t_err * 1000 << " mm, " << r_err << " deg\n";
  EXPECT_LT(t_err, 0.002) << "translation error " << t_err * 1000 << " mm";
  EXPECT_LT(r_err, 0.2) << "rotation error " << r_err << " deg";
  // The refinement must do better than the initial estimate from jittered per-view poses.
  EXPECT_LT(ext.rms_px, ext.initial_rms_px);
  EXPECT_LT(ext.rms_px, 0.5);  // 0.3 px noise per axis: about 0.42 px per corner
  EXPECT_GT(ext.iterations, 0);
  ASSERT_EQ(ext.views.size(), views.size());
  EXPECT_FALSE(ext.views[4].used);
  for (std::size_t i = 0; i < views.size(); ++i)
    if (i != 4) {
      EXPECT_TRUE(ext.views[i].used) << views[i].name;
    }
}

TEST(RigExtrinsics, ExactCornersGiveTheTruth) {
  const SyntheticRig rig;
  std::mt19937 rng(11);
  const auto views = stereo_views(rig, 5, 0.0, rng);
  const RigExtrinsics ext = solve_rig_extrinsics(rig.rgb, rig.fisheye, views);
  EXPECT_LT((ext.T_rgb_fisheye.translation - rig.T_rgb_fisheye.translation).norm(), 1e-6);
  EXPECT_LT(rotation_error_deg(ext.T_rgb_fisheye, rig.T_rgb_fisheye), 1e-4);
  EXPECT_LT(ext.rms_px, 1e-4);
}

TEST(RigExtrinsics, TooFewViewsIsAClearError) {
  const SyntheticRig rig;
  std::mt19937 rng(3);
  const auto views = stereo_views(rig, 2, 0.3, rng);
  try {
    solve_rig_extrinsics(rig.rgb, rig.fisheye, views);
    FAIL() << "two views were accepted";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("too few views for the extrinsics: both cameras saw "
                                         "the board in 2 views, at least 3"),
              std::string::npos)
        << e.what();
  }
}

TEST(RigExtrinsics, ViewsThatAllDisagreeAreAClearError) {
  const SyntheticRig rig;
  std::mt19937 rng(5);
  auto views = stereo_views(rig, 4, 0.3, rng);
  for (auto& v : views) v.T_fisheye_board = jittered(v.T_fisheye_board, 60, 0.1, rng);
  try {
    solve_rig_extrinsics(rig.rgb, rig.fisheye, views);
    FAIL() << "views with unrelated relative poses were accepted";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("the views disagree"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace probeless::calib
