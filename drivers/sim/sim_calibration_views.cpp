#include "drivers/sim/sim_calibration_views.hpp"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <numbers>

#include "drivers/sim/sim_rig.hpp"

namespace probeless::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

// One view: where the board's centre appears in one camera (a direction in that camera's
// frame), from how far, and how the line of sight leans from the board's normal.
struct View {
  enum class Camera { Colour, Fisheye } camera;
  // Colour: normalised image coordinates (x right, y down, 1 = one focal length from the
  // centre). Fisheye: angle from the optical axis and azimuth in the image (deg; -90 = the
  // top of the image, the rig's forward).
  double a, b;
  double distance_m;
  double tilt_deg, tilt_azimuth_deg;  // the camera seen from the board: off its normal
  double roll_deg;                    // about the line of sight
};

// Why these: Zhang's method needs boards tilted in different directions (20-40 deg, around
// several axes) to fix the focal lengths, and a lens's distortion and principal point are only
// measured where corners fall, so the views spread the board over each camera's whole image.
// The fisheye looks up, 90 deg from the colour camera: when the colour camera sees the board
// it lies 60-95 deg off the fisheye's axis, near the top rim of its image (the paired views,
// which also give the extrinsics); the calibrate helper measured that a fisheye calibrated
// from those alone has its principal point 1.8 px off. So the rig is then turned over the
// board until it has crossed the rest of the fisheye image (centre, the middle ring and the
// rim all round), where the colour camera sees the room instead. Colour views come first, so
// the colour camera's auto exposure (8 frames of memory) meters scenes like theirs.
constexpr std::array kViews{
    // Both cameras: the board in the upper half of the colour image, whole, at 0.65-0.75 m
    // (it then lies 63-92 deg off the fisheye's axis, inside its 95 deg), left, centre and
    // right, its normal leaning to either side and away from the rig by 15-35 deg.
    View{View::Camera::Colour, -0.22, -0.20, 0.70, 30, -90, 0},
    View{View::Camera::Colour, 0.00, -0.21, 0.70, 35, -60, 12},
    View{View::Camera::Colour, 0.22, -0.20, 0.70, 30, -120, -10},
    View{View::Camera::Colour, -0.20, -0.18, 0.72, 25, 0, 20},
    View{View::Camera::Colour, 0.20, -0.18, 0.72, 25, 180, -20},
    View{View::Camera::Colour, 0.00, -0.20, 0.65, 35, -90, 0},
    View{View::Camera::Colour, -0.24, -0.21, 0.70, 30, -30, -15},
    View{View::Camera::Colour, 0.24, -0.21, 0.70, 30, -150, 15},
    View{View::Camera::Colour, 0.00, -0.18, 0.75, 20, -90, 30},
    View{View::Camera::Colour, 0.10, -0.21, 0.70, 30, 120, -25},
    View{View::Camera::Colour, -0.10, -0.21, 0.70, 30, 60, 25},
    View{View::Camera::Colour, 0.00, -0.20, 0.70, 15, 90, 0},
    // The lower half of the colour image (the board leaves the fisheye's field there).
    View{View::Camera::Colour, -0.20, 0.15, 0.60, 30, -90, 10},
    View{View::Camera::Colour, 0.20, 0.15, 0.60, 30, 0, -10},
    View{View::Camera::Colour, 0.00, 0.18, 0.55, 35, 180, 0},
    // Both again, nearer (0.50-0.60 m) and higher in the colour image, cut by its top edge:
    // larger marker cells in the fisheye (5-6 px), whose rim they cover.
    View{View::Camera::Colour, -0.22, -0.28, 0.55, 30, -90, 0},
    View{View::Camera::Colour, 0.00, -0.29, 0.55, 35, -60, 12},
    View{View::Camera::Colour, 0.22, -0.28, 0.55, 30, -120, -10},
    View{View::Camera::Colour, -0.20, -0.26, 0.57, 25, 0, 20},
    View{View::Camera::Colour, 0.20, -0.26, 0.57, 25, 180, -20},
    View{View::Camera::Colour, 0.00, -0.28, 0.50, 35, -90, 0},
    View{View::Camera::Colour, -0.24, -0.29, 0.55, 30, -30, -15},
    View{View::Camera::Colour, 0.24, -0.29, 0.55, 30, -150, 15},
    View{View::Camera::Colour, 0.00, -0.26, 0.60, 20, -90, 30},
    View{View::Camera::Colour, 0.10, -0.29, 0.55, 30, 120, -25},
    View{View::Camera::Colour, -0.10, -0.29, 0.55, 30, 60, 25},
    View{View::Camera::Colour, 0.00, -0.28, 0.55, 15, 90, 0},
    // The colour camera alone, as a careful person finishes it: the board in the lower
    // corners, the bottom edge, both sides and the centre of the image at 0.55-0.60 m, tilted
    // 35-45 deg about the image's horizontal and its vertical axis (out of the fisheye's field).
    // Measured: the principal point's standard deviation 1.5, 1.2 -> 1.35, 1.09 px, the
    // extrinsics 0.080 -> 0.052 deg, eval light +14 -> +4.4 % (docs/calibration.md "Checked on
    // the sim"). Six more such views in the upper corners and the top edge, which the fisheye
    // then sees too, gave 0.038 deg but +21 %: left out.
    View{View::Camera::Colour, -0.32, 0.24, 0.55, 40, -60, 10},
    View{View::Camera::Colour, -0.32, 0.24, 0.55, 40, 30, -20},
    View{View::Camera::Colour, 0.32, 0.24, 0.55, 40, -120, -10},
    View{View::Camera::Colour, 0.32, 0.24, 0.55, 40, 150, 20},
    View{View::Camera::Colour, 0.00, 0.28, 0.55, 45, 0, 15},
    View{View::Camera::Colour, 0.00, 0.28, 0.55, 40, -90, -15},
    View{View::Camera::Colour, -0.40, 0.00, 0.55, 45, -90, 0},
    View{View::Camera::Colour, -0.40, 0.00, 0.55, 35, 90, 30},
    View{View::Camera::Colour, 0.40, 0.00, 0.55, 45, -90, 0},
    View{View::Camera::Colour, 0.40, 0.00, 0.55, 35, 90, -30},
    View{View::Camera::Colour, 0.00, 0.00, 0.60, 45, 45, 0},
    View{View::Camera::Colour, 0.00, 0.00, 0.60, 45, 135, 20},
    View{View::Camera::Colour, 0.00, 0.00, 0.60, 45, -45, -20},
    View{View::Camera::Colour, 0.00, 0.00, 0.60, 45, -135, 0},
    // The fisheye alone: its centre, a ring at 35 deg and one at 65 deg all round, its rim at
    // the sides and the bottom.
    View{View::Camera::Fisheye, 0, 0, 0.45, 25, 0, 0},
    View{View::Camera::Fisheye, 35, 0, 0.45, 30, 90, 20},
    View{View::Camera::Fisheye, 35, 90, 0.45, 30, 180, -20},
    View{View::Camera::Fisheye, 35, 180, 0.45, 30, -90, 40},
    View{View::Camera::Fisheye, 35, -90, 0.45, 30, 0, -40},
    View{View::Camera::Fisheye, 65, 45, 0.42, 25, 45, 0},
    View{View::Camera::Fisheye, 65, 135, 0.42, 25, 135, 30},
    View{View::Camera::Fisheye, 65, -135, 0.42, 25, -135, -30},
    View{View::Camera::Fisheye, 65, -45, 0.42, 25, -45, 0},
    View{View::Camera::Fisheye, 75, 0, 0.45, 20, 0, 0},
    View{View::Camera::Fisheye, 75, 90, 0.45, 20, 90, 0},
    View{View::Camera::Fisheye, 75, 180, 0.45, 20, 180, 0},
};

// An orthonormal frame whose first axis is `d` and second the part of `ref` across it.
Eigen::Matrix3d frame_along(const Eigen::Vector3d& d, Eigen::Vector3d ref) {
  if (std::abs(d.dot(ref.normalized())) > 0.95) ref = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d a = (ref - ref.dot(d) * d).normalized();
  Eigen::Matrix3d f;
  f << d, a, d.cross(a);
  return f;
}

Pose rig_pose_of(const View& v) {
  const bool colour = v.camera == View::Camera::Colour;
  // The board's centre in the camera's frame (OpenCV axes for both cameras).
  const Eigen::Vector3d in_camera =
      colour ? Eigen::Vector3d(v.a, v.b, 1).normalized()
             : Eigen::Vector3d(std::sin(v.a * kDeg) * std::cos(v.b * kDeg),
                               std::sin(v.a * kDeg) * std::sin(v.b * kDeg), std::cos(v.a * kDeg));
  const Eigen::Vector3d centre = board_world_pose().translation;
  const double tilt = v.tilt_deg * kDeg, azimuth = v.tilt_azimuth_deg * kDeg;
  const Eigen::Vector3d from_board(std::sin(tilt) * std::cos(azimuth),
                                   std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
  const Eigen::Vector3d to_board = -from_board;
  // Camera frame -> world: in_camera onto to_board, the camera's y axis (image down) onto
  // the world's -y (towards the person holding the rig) rolled by roll_deg about the line.
  const Eigen::Matrix3d cam = frame_along(in_camera, Eigen::Vector3d::UnitY());
  const Eigen::Vector3d world_ref =
      Eigen::AngleAxisd(v.roll_deg * kDeg, to_board) * -Eigen::Vector3d::UnitY();
  const Eigen::Matrix3d world = frame_along(to_board, world_ref);
  Pose T_world_camera;
  T_world_camera.rotation = Eigen::Quaterniond(world * cam.transpose()).normalized();
  T_world_camera.translation = centre + v.distance_m * from_board;
  return T_world_camera * (colour ? rgb_in_rig() : fisheye_in_rig()).inverse();
}

}  // namespace

int calibration_view_count() {
  return static_cast<int>(kViews.size());
}

Pose calibration_rig_pose(double t) {
  const auto n = static_cast<long long>(kViews.size());
  const long long i = static_cast<long long>(std::floor(t / kCalibrationHoldS + 1e-9)) % n;
  return rig_pose_of(kViews[static_cast<std::size_t>(i < 0 ? i + n : i)]);
}

}  // namespace probeless::sim
