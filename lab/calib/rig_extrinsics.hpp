#pragma once
// The pose of the fisheye relative to the colour camera from views in which both see the
// board (issue #18 item 1; thesis 4.2.2: point matches refined with Levenberg-Marquardt).
// 1. Each view gives one relative pose, T_fisheye_board * T_rgb_board^-1. The initial
//    estimate is robust to a few bad views: the medoid rotation (least summed angle to the
//    others), averaged over the views within kInlierAngleDeg of it, and the per-axis median
//    translation of those views.
// 2. Levenberg-Marquardt over that pose and every view's board pose, minimising the corners'
//    reprojection error in both cameras through core's camera models (so any model
//    core/camera has, OCamCalib's included, works unchanged); the intrinsics stay fixed.
// Pure Eigen: tested on synthetic corners with known truth (tests/unit/calib).
#include <string>
#include <vector>

#include "core/camera/camera_model.hpp"
#include "core/pose.hpp"

namespace probeless::calib {

struct StereoView {
  std::string name;
  std::vector<Eigen::Vector3d> rgb_points;  // board corners (board frame, metres) ...
  std::vector<Eigen::Vector2d> rgb_pixels;  // ... and where the colour camera saw them
  std::vector<Eigen::Vector3d> fisheye_points;
  std::vector<Eigen::Vector2d> fisheye_pixels;
  Pose T_rgb_board;  // initial board poses, from each camera's own calibration
  Pose T_fisheye_board;
};

struct StereoViewFit {
  std::string name;
  double rgb_rms_px = 0, fisheye_rms_px = 0;
  // Its relative pose agreed with the robust initial estimate, so the refinement used it;
  // the RMS of a view left out is measured with its colour camera's own board pose, and is
  // -1 when the extrinsics put its corners outside a model's domain.
  bool used = false;
};

struct RigExtrinsics {
  Pose T_rgb_fisheye;          // the fisheye in the colour camera's frame (refined)
  Pose initial_T_rgb_fisheye;  // the robust initial estimate
  double initial_rms_px = 0;   // both cameras' corners together, before and after
  double rms_px = 0;
  double rgb_rms_px = 0, fisheye_rms_px = 0;
  int iterations = 0;
  std::vector<StereoViewFit> views;
};

// Fewer views cannot outvote one wrong relative pose in the initial estimate.
inline constexpr int kMinStereoViews = 3;
inline constexpr double kInlierAngleDeg = 5.0;

// Throws CalibrationError (lab/calib/intrinsics.hpp) for fewer than kMinStereoViews views or
// views whose corners the models cannot project.
RigExtrinsics solve_rig_extrinsics(const CameraModel& rgb, const CameraModel& fisheye,
                                   const std::vector<StereoView>& views);

}  // namespace probeless::calib
