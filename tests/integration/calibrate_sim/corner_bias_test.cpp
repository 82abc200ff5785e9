// Where the board detector puts the sim's ChArUco corners against their true projections (the
// sim knows the board, each view's rig pose and both cameras' models): the mean signed error
// along each image's radial and tangential directions, by angle off the camera's axis. A bias
// here goes straight into the rig extrinsics: OpenCV 4.6's own ChArUco corners were +0.5 px in
// x and in y in both cameras (0.70 px RMS at every angle), 0.18 deg of T_rgb_fisheye
// (docs/calibration.md "Checked on the sim").
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/camera/kannala_brandt.hpp"
#include "drivers/sim/sim_board.hpp"
#include "drivers/sim/sim_calibration_views.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "lab/calib/board_detector.hpp"
#include "lab/calib/view_sources.hpp"

namespace probeless {
namespace {

constexpr double kDeg = 180 / std::numbers::pi;

// The corners in one band of angles off the axis.
struct Band {
  double lo_deg, hi_deg;
  int n = 0;
  double radial = 0, tangential = 0, squared = 0;
  double mean_radial() const { return n ? radial / n : 0; }
  double mean_tangential() const { return n ? tangential / n : 0; }
  double rms() const { return n ? std::sqrt(squared / n) : 0; }
};

struct CornerErrors {
  std::array<Band, 5> bands{Band{0, 30}, Band{30, 60}, Band{60, 75}, Band{75, 85}, Band{85, 96}};
  int views = 0;

  void add(const calib::BoardView& view, const CameraModel& camera, const Pose& T_world_camera,
           const Eigen::Vector2d& centre);
};

// A board point (OpenCV's board frame: x right, y down, z into the board) in the world: the
// board lies face up on its card, its top-left corner kMargin in from the card's (sim_board.cpp).
Eigen::Vector3d board_to_world(const Eigen::Vector3d& b) {
  const sim::BoardCard card = sim::board_card();
  constexpr double kMargin = 0.02;
  return {card.lo.x() + kMargin + b.x(), card.hi.y() - kMargin - b.y(), card.hi.z()};
}

void CornerErrors::add(const calib::BoardView& view, const CameraModel& camera,
                       const Pose& T_world_camera, const Eigen::Vector2d& centre) {
  ++views;
  const Pose T_camera_world = T_world_camera.inverse();
  for (std::size_t c = 0; c < view.pixels.size(); ++c) {
    const Eigen::Vector3d p = T_camera_world * board_to_world(view.points[c]);
    const auto truth = camera.project(p);
    ASSERT_TRUE(truth) << view.name << " corner " << view.ids[c];
    const double theta = std::acos(p.normalized().z()) * kDeg;
    const Eigen::Vector2d e = view.pixels[c] - *truth;
    const Eigen::Vector2d r = (*truth - centre).normalized();
    for (Band& b : bands) {
      if (theta < b.lo_deg || theta >= b.hi_deg) continue;
      ++b.n;
      b.radial += e.dot(r);
      b.tangential += r.x() * e.y() - r.y() * e.x();
      b.squared += e.squaredNorm();
    }
  }
}

TEST(CornerBias, ChArUcoCornersAreWhereTheSimProjectsThem) {
  const sim::SimOptions options = sim::parse_sim_options(
      "trajectory=calibration,fps=1,fisheye_fps=1,realtime=0,fisheye_size=1024");
  Rig rig = sim::make_sim_rig(options);
  const auto& fisheye = dynamic_cast<const KannalaBrandtCamera&>(*rig.calibration.fisheye);
  const calib::BoardDetector detector(parse_board_spec(sim::board_spec()));
  CornerErrors colour, fish;
  RgbdFrame rgbd;
  FisheyeFrame raw;
  for (int i = 0; i < sim::calibration_view_count(); ++i) {
    ASSERT_EQ(rig.rgbd->read(rgbd, std::chrono::milliseconds(1000)), ReadResult::Frame);
    ASSERT_EQ(rig.fisheye->read(raw, std::chrono::milliseconds(1000)), ReadResult::Frame);
    const std::string name = "view " + std::to_string(i);
    if (const auto v = detector.detect(calib::to_gray(rgbd.colour), name))
      colour.add(*v, rig.calibration.rgb, *rgbd.truth->rig_pose * rig.calibration.T_rig_rgb,
                 {rig.calibration.rgb.intrinsics().cx, rig.calibration.rgb.intrinsics().cy});
    if (const auto v = detector.detect(calib::fisheye_gray(raw), name))
      fish.add(*v, fisheye, *raw.truth->rig_pose * rig.calibration.T_rig_fisheye,
               {fisheye.params().cx, fisheye.params().cy});
  }
  EXPECT_EQ(colour.views, 41);
  EXPECT_EQ(fish.views, 36);
  // Measured: colour 0.08 px RMS; fisheye 0.07-0.19 px RMS, growing towards the rim where a
  // marker cell is 4-6 px; every band's mean under 0.04 px. Was 0.70 px RMS and +0.5 px in x
  // and in y everywhere.
  for (const auto* camera : {&colour, &fish}) {
    const char* name = camera == &colour ? "colour" : "fisheye";
    for (const Band& b : camera->bands) {
      if (b.n == 0) continue;
      std::printf(
          "%s, %2.0f-%2.0f deg off axis: %3d corners, mean radial %+.3f px, tangential "
          "%+.3f px, RMS %.3f px\n",
          name, b.lo_deg, b.hi_deg, b.n, b.mean_radial(), b.mean_tangential(), b.rms());
      EXPECT_LT(std::abs(b.mean_radial()), 0.06) << name << " " << b.lo_deg;
      EXPECT_LT(std::abs(b.mean_tangential()), 0.06) << name << " " << b.lo_deg;
      EXPECT_LT(b.rms(), 0.25) << name << " " << b.lo_deg;
    }
  }
}

}  // namespace
}  // namespace probeless
