#include "lab/calib/kannala_brandt_refine.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/camera/kannala_brandt.hpp"
#include "lab/calib/pose_step.hpp"

namespace probeless::calib {
namespace {

using Vector8d = Eigen::Matrix<double, 8, 1>;  // fx fy cx cy k1 k2 k3 k4

// core's projection without its domain check: during the refinement the domain is what the
// corners need (max_theta is set from the image circle afterwards).
Eigen::Vector2d project(const Vector8d& x, const Eigen::Vector3d& p) {
  const double r = std::hypot(p.x(), p.y());
  if (r == 0) return {x(2), x(3)};
  const double theta = std::atan2(r, p.z());
  const double s = kannala_brandt_distorted_angle({x(4), x(5), x(6), x(7)}, theta) / r;
  return {x(0) * s * p.x() + x(2), x(1) * s * p.y() + x(3)};
}

void residuals(const Vector8d& x, const BoardView& v, const Pose& T_camera_board,
               Eigen::VectorXd& r) {
  r.resize(2 * static_cast<Eigen::Index>(v.points.size()));
  for (std::size_t j = 0; j < v.points.size(); ++j)
    r.segment<2>(2 * static_cast<Eigen::Index>(j)) =
        project(x, T_camera_board * v.points[j]) - v.pixels[j];
}

double cost(const Vector8d& x, const std::vector<const BoardView*>& views,
            const std::vector<Pose>& poses) {
  double sum = 0;
  Eigen::VectorXd r;
  for (std::size_t i = 0; i < views.size(); ++i) {
    residuals(x, *views[i], poses[i], r);
    sum += r.squaredNorm();
  }
  return std::isfinite(sum) ? sum : std::numeric_limits<double>::infinity();
}

}  // namespace

Intrinsics refine_kannala_brandt(const std::vector<BoardView>& all_views,
                                 const Intrinsics& fisheye) {
  Vector8d x;
  x << fisheye.fx, fisheye.fy, fisheye.cx, fisheye.cy, 0, 0, 0, 0;
  for (std::size_t i = 0; i < 4 && i < fisheye.distortion.size(); ++i)
    x(4 + static_cast<Eigen::Index>(i)) = fisheye.distortion[i];
  std::vector<const BoardView*> views;
  std::vector<std::size_t> index;  // into all_views
  std::vector<Pose> poses;
  std::size_t corners = 0;
  for (std::size_t i = 0; i < all_views.size(); ++i) {
    if (!(fisheye.views[i].rms_px < kFailedStartMinPx)) continue;
    views.push_back(&all_views[i]);
    index.push_back(i);
    poses.push_back(fisheye.views[i].T_camera_board);
    corners += all_views[i].points.size();
  }
  if (static_cast<int>(views.size()) < kMinViews) return fisheye;

  // Levenberg-Marquardt with Marquardt's diagonal scaling and central-difference Jacobians; a
  // view's residuals touch the intrinsics and its own pose only, so the normal equations are
  // assembled block by block (8 + 6 per view: ~220 unknowns for 36 views).
  const Eigen::Index n = 8 + 6 * static_cast<Eigen::Index>(views.size());
  const Vector8d step = (Vector8d() << 1e-4, 1e-4, 1e-4, 1e-4, 1e-7, 1e-7, 1e-7, 1e-7).finished();
  constexpr double kPoseStep = 1e-7;  // radians / metres
  double current = cost(x, views, poses);
  const double initial = current;
  double lambda = 1e-3;
  for (int iteration = 0; iteration < 100; ++iteration) {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    for (std::size_t i = 0; i < views.size(); ++i) {
      Eigen::VectorXd r, plus, minus;
      residuals(x, *views[i], poses[i], r);
      Eigen::MatrixXd J(r.size(), 14);
      for (int p = 0; p < 8; ++p) {
        Vector8d d = Vector8d::Zero();
        d(p) = step(p);
        residuals(x + d, *views[i], poses[i], plus);
        residuals(x - d, *views[i], poses[i], minus);
        J.col(p) = (plus - minus) / (2 * step(p));
      }
      for (int p = 0; p < 6; ++p) {
        Vector6d d = Vector6d::Zero();
        d(p) = kPoseStep;
        residuals(x, *views[i], perturbed(poses[i], d), plus);
        residuals(x, *views[i], perturbed(poses[i], -d), minus);
        J.col(8 + p) = (plus - minus) / (2 * kPoseStep);
      }
      const Eigen::Index o = 8 + 6 * static_cast<Eigen::Index>(i);
      const Eigen::MatrixXd Jk = J.leftCols(8), Jp = J.rightCols(6);
      H.topLeftCorner(8, 8) += Jk.transpose() * Jk;
      H.block(0, o, 8, 6) += Jk.transpose() * Jp;
      H.block(o, 0, 6, 8) += Jp.transpose() * Jk;
      H.block(o, o, 6, 6) += Jp.transpose() * Jp;
      g.head(8) += Jk.transpose() * r;
      g.segment(o, 6) += Jp.transpose() * r;
    }
    bool improved = false;
    while (!improved && lambda < 1e10) {
      Eigen::MatrixXd A = H;
      A.diagonal() += lambda * H.diagonal();
      const Eigen::VectorXd delta = A.ldlt().solve(-g);
      const Vector8d x_new = x + delta.head(8);
      std::vector<Pose> poses_new = poses;
      for (std::size_t i = 0; i < views.size(); ++i)
        poses_new[i] = perturbed(poses[i], delta.segment<6>(8 + 6 * static_cast<Eigen::Index>(i)));
      const double c = cost(x_new, views, poses_new);
      if (c < current) {
        improved = true;
        const double gain = current - c;
        x = x_new;
        poses = std::move(poses_new);
        current = c;
        lambda = std::max(lambda / 10, 1e-12);
        if (gain < 1e-12 * current) iteration = 100;  // converged
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;
  }
  if (!(current < initial)) return fisheye;

  Intrinsics out = fisheye;
  out.fx = x(0);
  out.fy = x(1);
  out.cx = x(2);
  out.cy = x(3);
  out.distortion = {x(4), x(5), x(6), x(7)};
  out.rms_px = std::sqrt(current / static_cast<double>(corners));
  for (std::size_t i = 0; i < views.size(); ++i) {
    ViewFit& fit = out.views[index[i]];
    fit.in_fit = true;
    fit.T_camera_board = poses[i];
    const Eigen::Vector3d normal = poses[i].rotation * Eigen::Vector3d::UnitZ();
    fit.tilt_deg = std::acos(std::min(1.0, std::abs(normal.z()))) * 180.0 / std::numbers::pi;
    fit.reprojected.clear();
    double sum = 0;
    for (std::size_t j = 0; j < views[i]->points.size(); ++j) {
      fit.reprojected.push_back(project(x, poses[i] * views[i]->points[j]));
      sum += (fit.reprojected.back() - views[i]->pixels[j]).squaredNorm();
    }
    fit.rms_px = std::sqrt(sum / static_cast<double>(views[i]->points.size()));
  }
  return out;
}

}  // namespace probeless::calib
