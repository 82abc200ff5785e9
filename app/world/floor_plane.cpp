#include "app/world/floor_plane.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

namespace probeless::world {
namespace {

struct Plane {
  Eigen::Vector3d n;
  double d = 0;
};

// The plane through three points with its normal towards the camera (the origin); nullopt for
// a degenerate sample.
std::optional<Plane> plane_through(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                   const Eigen::Vector3d& c) {
  Eigen::Vector3d n = (b - a).cross(c - a);
  const double len = n.norm();
  if (len < 1e-9) return std::nullopt;
  n /= len;
  double d = -n.dot(a);
  if (d < 0) {
    n = -n;
    d = -d;
  }
  return Plane{n, d};
}

// Least-squares plane of the points: through their mean, normal along the smallest principal
// axis, oriented as `like`.
Plane fit(const std::vector<Eigen::Vector3d>& pts, const Plane& like) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Eigen::Vector3d n = eig.eigenvectors().col(0);
  if (n.dot(like.n) < 0) n = -n;
  return {n, -n.dot(mean)};
}

}  // namespace

std::optional<FloorPlane> find_floor(const DepthImage& depth_mm, const PinholeIntrinsics& k,
                                     const FloorParams& params) {
  if (depth_mm.width() != k.width || depth_mm.height() != k.height)
    throw std::invalid_argument("floor: the depth image is not the colour camera's size");
  std::vector<Eigen::Vector3d> pts;
  const int step = std::max(1, params.step);
  for (int y = step / 2; y < k.height; y += step)
    for (int x = step / 2; x < k.width; x += step) {
      const double z = depth_mm.at(x, y) * 1e-3;
      if (z < params.min_depth_m || z > params.max_depth_m) continue;
      pts.emplace_back((x - k.cx) / k.fx * z, (y - k.cy) / k.fy * z, z);
    }
  if (static_cast<int>(pts.size()) < std::max(3, params.min_inliers)) return std::nullopt;

  const Eigen::Vector3d up(0, -1, 0);
  const double min_cos = std::cos(params.max_tilt_deg * std::numbers::pi / 180.0);
  const auto acceptable = [&](const Plane& p) {
    return p.n.dot(up) >= min_cos && p.d >= params.min_camera_height_m;
  };
  const auto inlier = [&](const Plane& p, const Eigen::Vector3d& q) {
    return std::abs(p.n.dot(q) + p.d) < params.inlier_m;
  };
  std::mt19937_64 rng(params.seed);
  std::uniform_int_distribution<std::size_t> pick(0, pts.size() - 1);
  std::optional<Plane> best;
  int best_count = 0;
  for (int it = 0; it < params.iterations; ++it) {
    const auto p = plane_through(pts[pick(rng)], pts[pick(rng)], pts[pick(rng)]);
    if (!p || !acceptable(*p)) continue;
    int count = 0;
    for (const auto& q : pts) count += inlier(*p, q);
    if (count > best_count) {
      best_count = count;
      best = p;
    }
  }
  if (!best || best_count < params.min_inliers) return std::nullopt;

  // Two rounds of least squares on the inliers, the second on the refined plane's.
  Plane plane = *best;
  std::vector<Eigen::Vector3d> inliers;
  for (int round = 0; round < 2; ++round) {
    inliers.clear();
    for (const auto& q : pts)
      if (inlier(plane, q)) inliers.push_back(q);
    if (static_cast<int>(inliers.size()) < params.min_inliers) return std::nullopt;
    plane = fit(inliers, plane);
  }
  if (!acceptable(plane)) return std::nullopt;

  FloorPlane f;
  f.normal = plane.n;
  f.offset = plane.d;
  f.inliers = static_cast<int>(inliers.size());
  const Eigen::Vector3d axis(0, 0, 1);
  Eigen::Vector3d origin;
  const double along = -plane.n.dot(axis);  // > 0: the axis goes down towards the plane
  if (along > 1e-6 && plane.d / along <= params.max_depth_m) {
    origin = axis * (plane.d / along);
  } else {
    std::vector<double> zs;
    for (const auto& q : inliers) zs.push_back(q.z());
    std::nth_element(zs.begin(), zs.begin() + static_cast<long>(zs.size() / 2), zs.end());
    const Eigen::Vector3d p = axis * zs[zs.size() / 2];
    origin = p - (plane.n.dot(p) + plane.d) * plane.n;
  }
  const Eigen::Vector3d z_w = plane.n;
  Eigen::Vector3d y_w = axis - axis.dot(z_w) * z_w;
  if (y_w.norm() < 1e-6) y_w = Eigen::Vector3d(0, -1, 0) - Eigen::Vector3d(0, -1, 0).dot(z_w) * z_w;
  y_w.normalize();
  Eigen::Matrix3d r;
  r << y_w.cross(z_w), y_w, z_w;
  f.T_camera_floor.rotation = Eigen::Quaterniond(r).normalized();
  f.T_camera_floor.translation = origin;
  return f;
}

}  // namespace probeless::world
