#include "lab/eval/trajectory_metrics.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace probeless::eval {

Pose umeyama_rigid(const std::vector<Eigen::Vector3d>& src,
                   const std::vector<Eigen::Vector3d>& dst) {
  if (src.size() != dst.size())
    throw std::invalid_argument("umeyama_rigid: point sets of different sizes");
  if (src.size() < 3) throw std::invalid_argument("umeyama_rigid: fewer than 3 points");
  const double n = static_cast<double>(src.size());
  Eigen::Vector3d mu_s = Eigen::Vector3d::Zero(), mu_d = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < src.size(); ++i) {
    mu_s += src[i];
    mu_d += dst[i];
  }
  mu_s /= n;
  mu_d /= n;
  Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();  // cross-covariance, Umeyama eq. 38
  for (std::size_t i = 0; i < src.size(); ++i)
    sigma += (dst[i] - mu_d) * (src[i] - mu_s).transpose();
  sigma /= n;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d s = Eigen::Matrix3d::Identity();  // eq. 39: a reflection is not a rotation
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) s(2, 2) = -1;
  const Eigen::Matrix3d r = svd.matrixU() * s * svd.matrixV().transpose();
  Pose t;
  t.rotation = Eigen::Quaterniond(r).normalized();
  t.translation = mu_d - r * mu_s;
  return t;
}

std::optional<double> ate_rmse_m(const std::vector<PosePair>& frames) {
  std::vector<Eigen::Vector3d> est, truth;
  for (const auto& f : frames) {
    if (!f.truth) continue;
    est.push_back(f.estimate.translation);
    truth.push_back(f.truth->translation);
  }
  if (est.size() < 3) return std::nullopt;
  const Pose align = umeyama_rigid(est, truth);
  double sum = 0;
  for (std::size_t i = 0; i < est.size(); ++i) sum += (align * est[i] - truth[i]).squaredNorm();
  return std::sqrt(sum / static_cast<double>(est.size()));
}

namespace {

double angle_deg(const Eigen::Quaterniond& q) {
  return Eigen::AngleAxisd(q.normalized()).angle() * 180.0 / std::numbers::pi;
}

// Index of the timestamp closest to t in sorted `stamps` (evaluate_rpe.py's
// find_closest_index).
std::size_t closest_index(const std::vector<TimestampNs>& stamps, double t_ns) {
  const auto it = std::lower_bound(stamps.begin(), stamps.end(), t_ns, [](TimestampNs s, double t) {
    return static_cast<double>(s) < t;
  });
  std::size_t j = static_cast<std::size_t>(it - stamps.begin());
  if (j == stamps.size()) return j - 1;
  if (j > 0 && t_ns - static_cast<double>(stamps[j - 1]) < static_cast<double>(stamps[j]) - t_ns)
    --j;
  return j;
}

}  // namespace

std::optional<RelativePoseError> relative_pose_error(const std::vector<PosePair>& frames,
                                                     double delta_s) {
  if (frames.size() < 2) return std::nullopt;
  std::vector<TimestampNs> stamps;
  for (const auto& f : frames) stamps.push_back(f.timestamp_ns);
  if (!std::is_sorted(stamps.begin(), stamps.end()))
    throw std::invalid_argument("relative_pose_error: timestamps not increasing");
  RelativePoseError r;
  double sum_t = 0, sum_r = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::size_t j = closest_index(stamps, static_cast<double>(stamps[i]) + delta_s * 1e9);
    if (j == frames.size() - 1 || !frames[i].truth || !frames[j].truth) continue;
    const Pose truth_delta = frames[i].truth->inverse() * *frames[j].truth;
    const Pose est_delta = frames[i].estimate.inverse() * frames[j].estimate;
    const Pose error = truth_delta.inverse() * est_delta;
    sum_t += error.translation.squaredNorm();
    sum_r += std::pow(angle_deg(error.rotation), 2);
    ++r.pairs;
  }
  if (r.pairs == 0) return std::nullopt;
  r.translation_rmse_m = std::sqrt(sum_t / r.pairs);
  r.rotation_rmse_deg = std::sqrt(sum_r / r.pairs);
  return r;
}

std::vector<std::optional<double>> registration_px_per_frame(const std::vector<PosePair>& frames,
                                                             const PinholeIntrinsics& k,
                                                             const Eigen::Vector3d& point_first) {
  if (frames.empty()) return {};
  if (!frames.front().truth)
    throw std::invalid_argument("registration_px: the first frame has no ground truth");
  const auto project = [&](const Eigen::Vector3d& p) -> std::optional<Eigen::Vector2d> {
    if (p.z() <= 1e-6) return std::nullopt;
    return Eigen::Vector2d(k.fx * p.x() / p.z() + k.cx, k.fy * p.y() / p.z() + k.cy);
  };
  const double diagonal = std::hypot(k.width, k.height);
  const Pose est_first_inv = frames.front().estimate.inverse();
  const Pose truth_first_inv = frames.front().truth->inverse();
  std::vector<std::optional<double>> out;
  for (const auto& f : frames) {
    auto& px = out.emplace_back();
    if (!f.truth) continue;
    // T_camera_first = (T_first_world T_world_camera)^-1: the anchored point in this camera.
    const auto truth_px = project((truth_first_inv * *f.truth).inverse() * point_first);
    if (!truth_px || truth_px->x() < 0 || truth_px->y() < 0 || truth_px->x() >= k.width ||
        truth_px->y() >= k.height)
      continue;
    const auto est_px = project((est_first_inv * f.estimate).inverse() * point_first);
    px = est_px ? (*est_px - *truth_px).norm() : diagonal;
  }
  return out;
}

std::vector<double> registration_px(const std::vector<PosePair>& frames, const PinholeIntrinsics& k,
                                    const Eigen::Vector3d& point_first) {
  std::vector<double> out;
  for (const auto& px : registration_px_per_frame(frames, k, point_first))
    if (px) out.push_back(*px);
  return out;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

}  // namespace probeless::eval
