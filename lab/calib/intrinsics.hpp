#pragma once
// One camera's intrinsics from board views (issue #18 item 1, docs/calibration.md): the
// pinhole + Brown model (k1 k2 p1 p2 k3) through cv::calibrateCamera (Zhang 2000), or the
// Kannala-Brandt fisheye (k1..k4) through cv::fisheye::calibrate, whose model is exactly
// core/camera/kannala_brandt.hpp's.
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/camera/camera_model.hpp"
#include "core/camera/pinhole.hpp"
#include "core/pose.hpp"
#include "lab/calib/board_detector.hpp"

namespace probeless::calib {

// A calibration the views cannot support (too few, degenerate) or the solver refused; the
// message says what to do.
struct CalibrationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class LensModel { Pinhole, KannalaBrandt };
// "pinhole" or "kannala-brandt" (also "kannala_brandt", as the calibration TOML spells it).
std::optional<LensModel> parse_lens_model(std::string_view name);
std::string lens_model_name(LensModel model);  // as the --json report spells it

// Each planar view gives two constraints on the intrinsics (Zhang 2000, 3.1): with the four
// of K and the distortion, fewer than three views leave them undetermined.
inline constexpr int kMinViews = 3;
// The spread of the views' board orientations (the largest angle between two boards'
// normals) below which the calibration is refused: planes that differ by a translation only
// give the same constraint (Zhang 2000, 3.3), so focal length and distance trade off freely.
inline constexpr double kMinTiltSpreadDeg = 2.0;
// Below this spread the result is reported with a warning. Measured: the four ChArUco views
// of ../shared/data/aruco span 3.9 deg, and two more corners found at one view's edge move
// fx by 0.7 % (docs/calibration.md "Results").
inline constexpr double kWeakTiltSpreadDeg = 10.0;

// A Kannala-Brandt view whose reprojection after cv::fisheye::calibrate is above both of these
// (px; times the views' median) is solved again without it (calibrate_intrinsics).
inline constexpr double kFailedStartMinPx = 2.0, kFailedStartFactor = 10.0;

struct ViewFit {
  std::string name;
  int corners = 0;
  double rms_px = 0;
  double tilt_deg = 0;                       // between the board's normal and the optical axis
  Pose T_camera_board;                       // the board's pose in this view
  std::vector<Eigen::Vector2d> reprojected;  // the board's corners through the model
  // false: left out of the intrinsics (a fisheye view whose pose cv::fisheye failed to start,
  // posed afterwards through the fitted model; calibrate_intrinsics)
  bool in_fit = true;
};

struct Intrinsics {
  LensModel model = LensModel::Pinhole;
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> distortion;  // pinhole: k1 k2 p1 p2 k3; Kannala-Brandt: k1 k2 k3 k4
  double rms_px = 0;               // over all corners of the views in the fit
  // Pinhole: cv::calibrateCamera's standard deviations of fx fy cx cy k1 k2 p1 p2 k3 (px and
  // unitless), from its Jacobian and the residuals; how well the views pin each term down.
  // Empty for Kannala-Brandt (cv::fisheye::calibrate reports none).
  std::vector<double> std_dev;
  double tilt_spread_deg = 0;  // the largest angle between two views' board normals
  std::vector<ViewFit> views;  // in the order of the views given
  // Kannala-Brandt: the lens's image circle in focal lengths from the centre (image_circle.hpp),
  // where the model's domain ends; 0: the image is filled, the domain ends at its corners.
  double image_circle = 0;
  // The model as core/camera has it (PinholeCamera or KannalaBrandtCamera).
  std::shared_ptr<const CameraModel> camera() const;
  PinholeCamera pinhole() const;  // model == Pinhole
};

// Throws CalibrationError for fewer than kMinViews views, views of different sizes, views
// whose boards are nearly parallel, or a solver failure.
Intrinsics calibrate_intrinsics(const std::vector<BoardView>& views, LensModel model);

// The board's pose in one view through a camera whose model is known (any of core/camera:
// an imported OCamCalib fisheye too), and the view's reprojection through the model: PnP on
// the corners' rays (those within 80 deg of the axis, as points on the z = 1 plane). Throws
// CalibrationError when the model cannot unproject enough of the corners (a view of another camera,
// a wrong size). The pose is what PnP finds on the z = 1 plane; the rig's refinement improves it
// with the pixels.
ViewFit fit_board_pose(const CameraModel& camera, const BoardView& view);

// The largest angle from the axis the fitted Kannala-Brandt polynomial is valid to: where the
// image circle ends (Intrinsics::image_circle, else the farthest image corner), or earlier
// where theta_d(theta) stops increasing.
double kannala_brandt_max_theta(const Intrinsics& fisheye);

}  // namespace probeless::calib
