#include "lab/calib/rig_extrinsics.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "lab/calib/intrinsics.hpp"
#include "lab/calib/pose_step.hpp"

namespace probeless::calib {
namespace {

double angle_between(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Medoid rotation, averaged over the views near it; per-axis median translation of those.
Pose robust_initial(const std::vector<Pose>& relative, std::vector<bool>& inlier) {
  std::size_t best = 0;
  double best_sum = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < relative.size(); ++i) {
    double sum = 0;
    for (const Pose& other : relative) sum += angle_between(relative[i].rotation, other.rotation);
    if (sum < best_sum) best_sum = sum, best = i;
  }
  const double limit = kInlierAngleDeg * std::numbers::pi / 180.0;
  Eigen::Vector4d q_sum = Eigen::Vector4d::Zero();
  std::vector<double> tx, ty, tz;
  inlier.assign(relative.size(), false);
  for (std::size_t i = 0; i < relative.size(); ++i) {
    if (angle_between(relative[i].rotation, relative[best].rotation) > limit) continue;
    inlier[i] = true;
    Eigen::Vector4d q = relative[i].rotation.coeffs();
    if (q.dot(relative[best].rotation.coeffs()) < 0) q = -q;  // same hemisphere
    q_sum += q;
    tx.push_back(relative[i].translation.x());
    ty.push_back(relative[i].translation.y());
    tz.push_back(relative[i].translation.z());
  }
  Pose p;
  p.rotation = Eigen::Quaterniond(q_sum(3), q_sum(0), q_sum(1), q_sum(2)).normalized();
  p.translation = {median(tx), median(ty), median(tz)};
  return p;
}

// Reprojection residuals of one view: the colour camera's corners, then the fisheye's.
// False when a corner falls outside a model's domain.
bool view_residuals(const CameraModel& rgb, const CameraModel& fisheye, const StereoView& v,
                    const Pose& T_fisheye_rgb, const Pose& T_rgb_board, Eigen::VectorXd& r) {
  r.resize(2 * static_cast<Eigen::Index>(v.rgb_points.size() + v.fisheye_points.size()));
  Eigen::Index k = 0;
  for (std::size_t j = 0; j < v.rgb_points.size(); ++j) {
    const auto px = rgb.project(T_rgb_board * v.rgb_points[j]);
    if (!px) return false;
    r.segment<2>(k) = *px - v.rgb_pixels[j];
    k += 2;
  }
  const Pose T_fisheye_board = T_fisheye_rgb * T_rgb_board;
  for (std::size_t j = 0; j < v.fisheye_points.size(); ++j) {
    const auto px = fisheye.project(T_fisheye_board * v.fisheye_points[j]);
    if (!px) return false;
    r.segment<2>(k) = *px - v.fisheye_pixels[j];
    k += 2;
  }
  return true;
}

struct Problem {
  const CameraModel& rgb;
  const CameraModel& fisheye;
  const std::vector<StereoView>& views;

  // Sum of squared residuals; infinity when a corner leaves a model's domain.
  double cost(const Pose& T_fisheye_rgb, const std::vector<Pose>& boards) const {
    double sum = 0;
    Eigen::VectorXd r;
    for (std::size_t i = 0; i < views.size(); ++i) {
      if (!view_residuals(rgb, fisheye, views[i], T_fisheye_rgb, boards[i], r))
        return std::numeric_limits<double>::infinity();
      sum += r.squaredNorm();
    }
    return sum;
  }
};

}  // namespace

RigExtrinsics solve_rig_extrinsics(const CameraModel& rgb, const CameraModel& fisheye,
                                   const std::vector<StereoView>& all_views) {
  if (static_cast<int>(all_views.size()) < kMinStereoViews)
    throw CalibrationError(fmt::format(
        "too few views for the extrinsics: both cameras saw the board in {} view{}, at least "
        "{} are needed (hold the board where both cameras see it, in several poses)",
        all_views.size(), all_views.size() == 1 ? "" : "s", kMinStereoViews));
  std::vector<Pose> relative;
  for (const StereoView& v : all_views)
    relative.push_back(v.T_fisheye_board * v.T_rgb_board.inverse());
  std::vector<bool> inlier;
  Pose T_fisheye_rgb = robust_initial(relative, inlier);
  // A view whose relative pose disagrees with the others (a corner ordering flipped in one
  // camera, a board pose caught mid-motion) would pull the least-squares fit: it is left out.
  std::vector<StereoView> views;
  for (std::size_t i = 0; i < all_views.size(); ++i)
    if (inlier[i]) views.push_back(all_views[i]);
  if (static_cast<int>(views.size()) < kMinStereoViews)
    throw CalibrationError(fmt::format(
        "the views disagree: only {} of {} give a fisheye-to-colour rotation within {:.0f} deg "
        "of the others, at least {} are needed (check each camera's views in --views-out)",
        views.size(), all_views.size(), kInlierAngleDeg, kMinStereoViews));
  std::vector<Pose> boards;
  for (const StereoView& v : views) boards.push_back(v.T_rgb_board);

  const Problem problem{rgb, fisheye, views};
  double cost = problem.cost(T_fisheye_rgb, boards);
  if (!std::isfinite(cost))
    throw CalibrationError(
        "the initial extrinsics put board corners outside a camera model's domain: the "
        "per-camera board poses disagree (look at --views-out)");
  std::size_t residual_count = 0;
  for (const StereoView& v : views) residual_count += v.rgb_points.size() + v.fisheye_points.size();

  RigExtrinsics out;
  out.initial_T_rgb_fisheye = T_fisheye_rgb.inverse();
  out.initial_rms_px = std::sqrt(cost / static_cast<double>(residual_count));

  // Levenberg-Marquardt (Marquardt's diagonal scaling) on [shared pose, board pose per view]
  // with central-difference Jacobians; each view's residuals touch only its own board pose
  // and the shared one, so the normal equations are assembled block by block.
  const Eigen::Index n = 6 + 6 * static_cast<Eigen::Index>(views.size());
  constexpr double kStep = 1e-7;  // radians / metres
  double lambda = 1e-3;
  bool converged = false;
  for (int iteration = 0; iteration < 100 && !converged; ++iteration) {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    for (std::size_t i = 0; i < views.size(); ++i) {
      Eigen::VectorXd r, plus, minus;
      view_residuals(rgb, fisheye, views[i], T_fisheye_rgb, boards[i], r);
      Eigen::MatrixXd J(r.size(), 12);
      for (int p = 0; p < 12; ++p) {
        Vector6d d = Vector6d::Zero();
        d(p % 6) = kStep;
        const bool shared = p < 6;
        const Pose s_plus = shared ? perturbed(T_fisheye_rgb, d) : T_fisheye_rgb;
        const Pose s_minus = shared ? perturbed(T_fisheye_rgb, -d) : T_fisheye_rgb;
        const Pose b_plus = shared ? boards[i] : perturbed(boards[i], d);
        const Pose b_minus = shared ? boards[i] : perturbed(boards[i], -d);
        if (!view_residuals(rgb, fisheye, views[i], s_plus, b_plus, plus) ||
            !view_residuals(rgb, fisheye, views[i], s_minus, b_minus, minus)) {
          J.col(p).setZero();  // at the domain's edge: no information along this direction
          continue;
        }
        J.col(p) = (plus - minus) / (2 * kStep);
      }
      const Eigen::Index o = 6 + 6 * static_cast<Eigen::Index>(i);
      const auto Js = J.leftCols<6>();
      const auto Jb = J.rightCols<6>();
      H.topLeftCorner<6, 6>() += Js.transpose() * Js;
      H.block<6, 6>(o, o) += Jb.transpose() * Jb;
      H.block<6, 6>(0, o) += Js.transpose() * Jb;
      H.block<6, 6>(o, 0) += Jb.transpose() * Js;
      g.head<6>() += Js.transpose() * r;
      g.segment<6>(o) += Jb.transpose() * r;
    }
    bool improved = false;
    while (!improved && lambda < 1e10) {
      Eigen::MatrixXd A = H;
      A.diagonal() += lambda * H.diagonal().cwiseMax(1e-9);
      const Eigen::VectorXd delta = A.ldlt().solve(-g);
      const Pose trial_shared = perturbed(T_fisheye_rgb, delta.head<6>());
      std::vector<Pose> trial_boards(boards.size());
      for (std::size_t i = 0; i < boards.size(); ++i)
        trial_boards[i] =
            perturbed(boards[i], delta.segment<6>(6 + 6 * static_cast<Eigen::Index>(i)));
      const double trial = problem.cost(trial_shared, trial_boards);
      if (trial < cost) {
        const double gain = (cost - trial) / cost;
        T_fisheye_rgb = trial_shared;
        boards = std::move(trial_boards);
        cost = trial;
        lambda = std::max(lambda / 10, 1e-12);
        improved = true;
        out.iterations = iteration + 1;
        converged = gain < 1e-12 || delta.norm() < 1e-12;
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;
  }

  out.T_rgb_fisheye = T_fisheye_rgb.inverse();
  out.rms_px = std::sqrt(cost / static_cast<double>(residual_count));
  double rgb_sum = 0, fisheye_sum = 0;
  std::size_t rgb_n = 0, fisheye_n = 0, used = 0;
  for (std::size_t i = 0; i < all_views.size(); ++i) {
    const StereoView& v = all_views[i];
    Eigen::VectorXd r;
    const Pose& board = inlier[i] ? boards[used++] : v.T_rgb_board;
    if (!view_residuals(rgb, fisheye, v, T_fisheye_rgb, board, r)) {
      out.views.push_back({v.name, -1, -1, false});  // outside a model's domain: no figure
      continue;
    }
    const Eigen::Index m = 2 * static_cast<Eigen::Index>(v.rgb_points.size());
    const double a = r.head(m).squaredNorm(), b = r.tail(r.size() - m).squaredNorm();
    if (inlier[i]) {
      rgb_sum += a;
      fisheye_sum += b;
      rgb_n += v.rgb_points.size();
      fisheye_n += v.fisheye_points.size();
    }
    out.views.push_back(
        {v.name, std::sqrt(a / static_cast<double>(std::max<std::size_t>(1, v.rgb_points.size()))),
         std::sqrt(b / static_cast<double>(std::max<std::size_t>(1, v.fisheye_points.size()))),
         inlier[i]});
  }
  out.rgb_rms_px = std::sqrt(rgb_sum / static_cast<double>(std::max<std::size_t>(1, rgb_n)));
  out.fisheye_rms_px =
      std::sqrt(fisheye_sum / static_cast<double>(std::max<std::size_t>(1, fisheye_n)));
  return out;
}

}  // namespace probeless::calib
