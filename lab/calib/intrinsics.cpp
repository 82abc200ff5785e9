#include "lab/calib/intrinsics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

#include "core/camera/kannala_brandt.hpp"
#include "core/camera/pinhole.hpp"
#include "lab/calib/kannala_brandt_refine.hpp"

namespace probeless::calib {
namespace {

// Single precision: cv::calibrateCamera takes nothing else (and corners are not more precise).
struct Correspondences {
  std::vector<std::vector<cv::Point3f>> points;
  std::vector<std::vector<cv::Point2f>> pixels;
};

Correspondences correspondences(const std::vector<BoardView>& views) {
  Correspondences c;
  for (const BoardView& v : views) {
    auto& pts = c.points.emplace_back();
    auto& px = c.pixels.emplace_back();
    for (const auto& p : v.points) pts.emplace_back(cv::Point3d(p.x(), p.y(), p.z()));
    for (const auto& p : v.pixels) px.emplace_back(cv::Point2d(p.x(), p.y()));
  }
  return c;
}

Pose pose_from(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d r;
  cv::cv2eigen(R, r);
  Pose p;
  p.rotation = Eigen::Quaterniond(r);
  p.translation = {tvec[0], tvec[1], tvec[2]};
  return p;
}

// Largest angle between the board normals of any two views.
double tilt_spread_deg(const std::vector<ViewFit>& fits) {
  double widest = 0;
  for (std::size_t i = 0; i < fits.size(); ++i)
    for (std::size_t j = i + 1; j < fits.size(); ++j) {
      const Eigen::Vector3d a = fits[i].T_camera_board.rotation * Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d b = fits[j].T_camera_board.rotation * Eigen::Vector3d::UnitZ();
      widest = std::max(widest, std::acos(std::clamp(a.dot(b), -1.0, 1.0)));
    }
  return widest * 180.0 / std::numbers::pi;
}

void check_views(const std::vector<BoardView>& views) {
  if (static_cast<int>(views.size()) < kMinViews)
    throw CalibrationError(fmt::format(
        "too few views: the board was found in {} image{}, at least {} are needed (show the "
        "board whole, tilted in different directions)",
        views.size(), views.size() == 1 ? "" : "s", kMinViews));
  for (const BoardView& v : views)
    if (v.width != views.front().width || v.height != views.front().height)
      throw CalibrationError(fmt::format("{} is {}x{} but {} is {}x{}: one camera, one size",
                                         v.name, v.width, v.height, views.front().name,
                                         views.front().width, views.front().height));
}

}  // namespace

std::optional<LensModel> parse_lens_model(std::string_view name) {
  if (name == "pinhole") return LensModel::Pinhole;
  if (name == "kannala-brandt" || name == "kannala_brandt") return LensModel::KannalaBrandt;
  return std::nullopt;
}

std::string lens_model_name(LensModel model) {
  return model == LensModel::Pinhole ? "pinhole" : "kannala-brandt";
}

namespace {

// One solve of OpenCV's calibration over `views`: the intrinsics and each view's fit.
Intrinsics solve(const std::vector<BoardView>& views, LensModel model) {
  const Correspondences c = correspondences(views);
  const cv::Size size(views.front().width, views.front().height);
  cv::Mat K, D, std_intrinsics;
  std::vector<cv::Vec3d> rvecs, tvecs;
  try {
    if (model == LensModel::Pinhole) {
      cv::calibrateCamera(
          c.points, c.pixels, size, K, D, rvecs, tvecs, std_intrinsics, cv::noArray(),
          cv::noArray(), 0,
          cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
    } else {
      // cv::fisheye wants 1xN arrays of 3- and 2-channel points.
      std::vector<cv::Mat> points, pixels;
      for (std::size_t i = 0; i < views.size(); ++i) {
        points.push_back(cv::Mat(c.points[i]).reshape(3, 1));
        pixels.push_back(cv::Mat(c.pixels[i]).reshape(2, 1));
      }
      cv::Matx33d Kf;
      cv::Vec4d Df;
      // Skew fixed at zero (core's model has none); extrinsics recomputed every iteration,
      // without which the solver often diverges from its initial guess.
      cv::fisheye::calibrate(
          points, pixels, size, Kf, Df, rvecs, tvecs,
          cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW,
          cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
      K = cv::Mat(Kf);
      D = cv::Mat(Df);
    }
  } catch (const cv::Exception& e) {
    throw CalibrationError(fmt::format(
        "the {} calibration failed on these {} views ({}): the views may be too few, too "
        "similar or the corners wrong; look at --views-out",
        lens_model_name(model), views.size(), e.err));
  }

  Intrinsics out;
  out.model = model;
  out.width = size.width;
  out.height = size.height;
  K.convertTo(K, CV_64F);
  D.convertTo(D, CV_64F);
  out.fx = K.at<double>(0, 0);
  out.fy = K.at<double>(1, 1);
  out.cx = K.at<double>(0, 2);
  out.cy = K.at<double>(1, 2);
  out.distortion.assign(D.begin<double>(), D.end<double>());
  if (!std_intrinsics.empty()) {
    // OpenCV's order: fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6 s1..s4 tx ty; the model fits 9.
    std_intrinsics.convertTo(std_intrinsics, CV_64F);
    const auto n = std::min<std::size_t>(4 + out.distortion.size(), std_intrinsics.total());
    out.std_dev.assign(std_intrinsics.begin<double>(),
                       std_intrinsics.begin<double>() + static_cast<long>(n));
  }
  if (!std::isfinite(out.fx) || !std::isfinite(out.fy) || !(out.fx > 0) || !(out.fy > 0))
    throw CalibrationError(
        fmt::format("the {} calibration gave no usable focal length (fx {}, fy {}): the views "
                    "are degenerate",
                    lens_model_name(model), out.fx, out.fy));

  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < views.size(); ++i) {
    std::vector<cv::Point2f> projected;
    if (model == LensModel::Pinhole) {
      cv::projectPoints(c.points[i], rvecs[i], tvecs[i], K, D, projected);
    } else {
      cv::fisheye::projectPoints(c.points[i], projected, rvecs[i], tvecs[i], K, D);
    }
    ViewFit fit;
    fit.name = views[i].name;
    fit.corners = static_cast<int>(projected.size());
    fit.T_camera_board = pose_from(rvecs[i], tvecs[i]);
    const Eigen::Vector3d normal = fit.T_camera_board.rotation * Eigen::Vector3d::UnitZ();
    fit.tilt_deg = std::acos(std::min(1.0, std::abs(normal.z()))) * 180.0 / std::numbers::pi;
    double view_sum = 0;
    for (std::size_t j = 0; j < projected.size(); ++j) {
      const cv::Point2d e = cv::Point2d(projected[j]) - cv::Point2d(c.pixels[i][j]);
      view_sum += e.dot(e);
      fit.reprojected.emplace_back(projected[j].x, projected[j].y);
    }
    fit.rms_px = std::sqrt(view_sum / static_cast<double>(projected.size()));
    sum += view_sum;
    n += projected.size();
    out.views.push_back(std::move(fit));
  }
  out.rms_px = std::sqrt(sum / static_cast<double>(n));
  return out;
}

// cv::fisheye::calibrate starts each view's pose from a homography of its corners undistorted
// by the initial guess (k = 0) onto the z = 1 plane; corners 80-95 deg off the axis land near
// infinity there, and such a view can keep a wrong pose hundreds of pixels off while the
// others fit to 0.1 px (measured on the sim's calibration views, docs/calibration.md "Checked
// on the sim"). Its corners are fine: posed through the fitted model they reproject to
// ~0.1 px. So a view this far above the others is a failed start, not a bad view.
bool failed_start(double rms_px, double median_rms_px) {
  return rms_px > std::max(kFailedStartMinPx, kFailedStartFactor * median_rms_px);
}

}  // namespace

Intrinsics calibrate_intrinsics(const std::vector<BoardView>& views, LensModel model) {
  check_views(views);
  Intrinsics out = solve(views, model);
  if (model == LensModel::KannalaBrandt) {
    std::vector<double> rms;
    for (const ViewFit& f : out.views) rms.push_back(f.rms_px);
    std::nth_element(rms.begin(), rms.begin() + static_cast<long>(rms.size() / 2), rms.end());
    const double median = rms[rms.size() / 2];
    std::vector<BoardView> kept;
    for (std::size_t i = 0; i < views.size(); ++i)
      if (!failed_start(out.views[i].rms_px, median)) kept.push_back(views[i]);
    if (kept.size() < views.size() && static_cast<int>(kept.size()) >= kMinViews) {
      // Solve again without them, then pose them through the result (PnP on its rays).
      const Intrinsics again = solve(kept, model);
      const auto camera = again.camera();
      std::vector<ViewFit> fits;
      double sum = 0;
      std::size_t n = 0, k = 0;
      for (std::size_t i = 0; i < views.size(); ++i) {
        const bool was_kept = failed_start(out.views[i].rms_px, median) == false;
        ViewFit fit = was_kept ? again.views[k++] : fit_board_pose(*camera, views[i]);
        fit.in_fit = was_kept;
        if (was_kept) {
          sum += fit.rms_px * fit.rms_px * fit.corners;
          n += static_cast<std::size_t>(fit.corners);
        }
        fits.push_back(std::move(fit));
      }
      out = again;
      out.views = std::move(fits);
      out.rms_px = std::sqrt(sum / static_cast<double>(n));
    }
  }

  if (model == LensModel::KannalaBrandt) out = refine_kannala_brandt(views, out);

  const double spread = out.tilt_spread_deg = tilt_spread_deg(out.views);
  if (spread < kMinTiltSpreadDeg)
    throw CalibrationError(fmt::format(
        "degenerate views: the board's orientation differs by at most {:.1f} deg across the "
        "{} views (at least {:.0f} deg needed; tilt it by 20-40 deg in different directions)",
        spread, views.size(), kMinTiltSpreadDeg));
  return out;
}

PinholeCamera Intrinsics::pinhole() const {
  PinholeIntrinsics k{width, height, fx, fy, cx, cy};
  BrownDistortion d;
  const auto coeff = [&](std::size_t i) { return i < distortion.size() ? distortion[i] : 0.0; };
  d.k1 = coeff(0);
  d.k2 = coeff(1);
  d.p1 = coeff(2);
  d.p2 = coeff(3);
  d.k3 = coeff(4);
  return PinholeCamera(k, d);
}

std::shared_ptr<const CameraModel> Intrinsics::camera() const {
  if (model == LensModel::Pinhole) return std::make_shared<PinholeCamera>(pinhole());
  KannalaBrandtParams p;
  p.width = width;
  p.height = height;
  p.fx = fx;
  p.fy = fy;
  p.cx = cx;
  p.cy = cy;
  for (std::size_t i = 0; i < 4 && i < distortion.size(); ++i) p.k[i] = distortion[i];
  p.max_theta = kannala_brandt_max_theta(*this);
  return std::make_shared<KannalaBrandtCamera>(p);
}

double kannala_brandt_max_theta(const Intrinsics& f) {
  std::array<double, 4> k{};
  for (std::size_t i = 0; i < 4 && i < f.distortion.size(); ++i) k[i] = f.distortion[i];
  double corner = 0;  // the farthest image corner's theta_d (focal lengths)
  for (double u : {-0.5, f.width - 0.5})
    for (double v : {-0.5, f.height - 0.5})
      corner = std::max(corner, std::hypot((u - f.cx) / f.fx, (v - f.cy) / f.fy));
  if (f.image_circle > 0) corner = std::min(corner, f.image_circle);
  constexpr double kStep = 1e-4;
  double theta = 0, theta_d = 0;
  while (theta < std::numbers::pi) {
    const double next = kannala_brandt_distorted_angle(k, theta + kStep);
    if (next <= theta_d) break;  // the polynomial folds back here
    theta += kStep;
    theta_d = next;
    if (theta_d >= corner) break;
  }
  return theta;
}

}  // namespace probeless::calib

namespace probeless::calib {

ViewFit fit_board_pose(const CameraModel& camera, const BoardView& view) {
  if (view.width != camera.width() || view.height != camera.height())
    throw CalibrationError(fmt::format("{} is {}x{} but the camera's model is {}x{}", view.name,
                                       view.width, view.height, camera.width(), camera.height()));
  // PnP on the rays put on a plane facing the board: a virtual camera turned towards the
  // corners' mean ray, so a board near a fisheye's rim (80-95 deg off its axis) is posed as
  // well as one at its centre. Rays beyond 80 deg of that direction land too far out on the
  // plane to weigh sensibly.
  std::vector<Eigen::Vector3d> rays;
  std::vector<std::size_t> index;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < view.pixels.size(); ++i)
    if (const auto ray = camera.unproject(view.pixels[i])) {
      rays.push_back(ray->normalized());
      index.push_back(i);
      mean += rays.back();
    }
  const Eigen::Matrix3d to_virtual =
      mean.norm() > 0
          ? Eigen::Quaterniond::FromTwoVectors(mean, Eigen::Vector3d::UnitZ()).toRotationMatrix()
          : Eigen::Matrix3d::Identity();
  const double min_z = std::cos(80.0 * std::numbers::pi / 180.0);
  std::vector<cv::Point3d> points;
  std::vector<cv::Point2d> plane;
  for (std::size_t k = 0; k < rays.size(); ++k) {
    const Eigen::Vector3d r = to_virtual * rays[k];
    if (r.z() < min_z) continue;
    const Eigen::Vector3d& p = view.points[index[k]];
    points.emplace_back(p.x(), p.y(), p.z());
    plane.emplace_back(r.x() / r.z(), r.y() / r.z());
  }
  if (points.size() < 6)
    throw CalibrationError(fmt::format(
        "{}: only {} of its {} corners are within the camera model's field of view: is it a "
        "view of this camera?",
        view.name, points.size(), view.pixels.size()));
  cv::Vec3d rvec, tvec;
  if (!cv::solvePnP(points, plane, cv::Matx33d::eye(), cv::noArray(), rvec, tvec))
    throw CalibrationError(view.name + ": no board pose found for the camera's model");
  Pose from_virtual;
  from_virtual.rotation = Eigen::Quaterniond(to_virtual.transpose());
  ViewFit fit;
  fit.name = view.name;
  fit.corners = static_cast<int>(view.pixels.size());
  fit.T_camera_board = from_virtual * pose_from(rvec, tvec);
  const Eigen::Vector3d normal = fit.T_camera_board.rotation * Eigen::Vector3d::UnitZ();
  fit.tilt_deg = std::acos(std::min(1.0, std::abs(normal.z()))) * 180.0 / std::numbers::pi;
  double sum = 0;
  for (std::size_t i = 0; i < view.pixels.size(); ++i) {
    const auto px = camera.project(fit.T_camera_board * view.points[i]);
    const Eigen::Vector2d p = px ? *px : Eigen::Vector2d(-1e6, -1e6);  // shows as a huge error
    fit.reprojected.push_back(p);
    sum += (p - view.pixels[i]).squaredNorm();
  }
  fit.rms_px = std::sqrt(sum / static_cast<double>(view.pixels.size()));
  return fit;
}

}  // namespace probeless::calib
