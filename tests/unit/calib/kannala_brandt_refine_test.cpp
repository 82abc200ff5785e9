// The joint refinement of a Kannala-Brandt calibration: from exact corners and a start 1 % and
// 2 px off (as cv::fisheye::calibrate can stop), it lands on the truth; views too far off
// stay out; too few views leave the calibration as it was.
#include "lab/calib/kannala_brandt_refine.hpp"

#include <gtest/gtest.h>

#include "core/camera/kannala_brandt.hpp"
#include "synthetic_board.hpp"

namespace probeless::calib {
namespace {

using namespace testing;

struct StartingPoint {
  std::vector<BoardView> views;
  Intrinsics start;  // the truth perturbed, each view's pose too
};

StartingPoint make_start(const KannalaBrandtCamera& truth, int count) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> xy(-0.15, 0.15), tilt(-40, 40), spin(-180, 180);
  StartingPoint s;
  s.start.model = LensModel::KannalaBrandt;
  s.start.width = truth.width();
  s.start.height = truth.height();
  const auto& p = truth.params();
  s.start.fx = p.fx * 1.01;
  s.start.fy = p.fy * 0.99;
  s.start.cx = p.cx + 2;
  s.start.cy = p.cy - 2;
  s.start.distortion = {p.k[0] + 0.005, p.k[1], p.k[2], p.k[3]};
  while (static_cast<int>(s.views.size()) < count) {
    const Pose pose = board_pose({xy(rng), xy(rng), 0.35}, tilt(rng), tilt(rng), spin(rng));
    auto px = project_board(truth, pose, 0.0, rng);
    if (px.empty()) continue;
    s.views.push_back(board_view(std::to_string(s.views.size()), truth, px));
    ViewFit fit;
    fit.name = s.views.back().name;
    fit.corners = static_cast<int>(px.size());
    fit.rms_px = 1.0;  // below kFailedStartMinPx: takes part
    fit.T_camera_board = pose;
    fit.T_camera_board.translation += Eigen::Vector3d(0.002, -0.001, 0.003);
    s.start.views.push_back(fit);
  }
  return s;
}

TEST(KannalaBrandtRefine, ExactCornersFromAStartOffGiveTheTruth) {
  const KannalaBrandtCamera truth(
      KannalaBrandtParams{800, 800, 250, 251, 402, 397, {0.03, -0.01, 0.002, 0}, 1.7});
  StartingPoint s = make_start(truth, 10);
  s.start.views[3].rms_px = kFailedStartMinPx + 1;  // a failed start stays out
  s.start.views[3].in_fit = false;
  const Intrinsics out = refine_kannala_brandt(s.views, s.start);
  EXPECT_NEAR(out.fx, 250, 1e-6);
  EXPECT_NEAR(out.fy, 251, 1e-6);
  EXPECT_NEAR(out.cx, 402, 1e-6);
  EXPECT_NEAR(out.cy, 397, 1e-6);
  ASSERT_EQ(out.distortion.size(), 4u);
  EXPECT_NEAR(out.distortion[0], 0.03, 1e-7);
  EXPECT_NEAR(out.distortion[1], -0.01, 1e-7);
  EXPECT_LT(out.rms_px, 1e-6);
  ASSERT_EQ(out.views.size(), 10u);
  EXPECT_FALSE(out.views[3].in_fit);
  EXPECT_EQ(out.views[3].rms_px, kFailedStartMinPx + 1);  // kept as it was
  EXPECT_TRUE(out.views[0].in_fit);
  EXPECT_LT(out.views[0].rms_px, 1e-6);
  EXPECT_EQ(out.views[0].reprojected.size(), s.views[0].pixels.size());
}

TEST(KannalaBrandtRefine, TooFewViewsLeaveTheCalibrationAsItWas) {
  const KannalaBrandtCamera truth(
      KannalaBrandtParams{800, 800, 250, 251, 402, 397, {0.03, -0.01, 0.002, 0}, 1.7});
  StartingPoint s = make_start(truth, kMinViews);
  s.start.views[0].rms_px = kFailedStartMinPx * 2;
  const Intrinsics out = refine_kannala_brandt(s.views, s.start);
  EXPECT_EQ(out.fx, s.start.fx);
  EXPECT_EQ(out.cx, s.start.cx);
  EXPECT_EQ(out.views[1].rms_px, 1.0);
}

}  // namespace
}  // namespace probeless::calib
