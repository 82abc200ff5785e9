#include "core/camera/kannala_brandt.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace probeless {

double kannala_brandt_distorted_angle(const std::array<double, 4>& k, double theta) {
  const double t2 = theta * theta;
  return theta * (1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
}

KannalaBrandtCamera::KannalaBrandtCamera(KannalaBrandtParams p) : p_(p) {
  if (p_.width <= 0 || p_.height <= 0 || !(p_.fx > 0) || !(p_.fy > 0) || !(p_.max_theta > 0))
    throw std::invalid_argument(
        "KannalaBrandtCamera: size, focal lengths and max_theta must be "
        "positive");
}

KannalaBrandtCamera KannalaBrandtCamera::equidistant(int size, double fov_deg) {
  const double half_fov = 0.5 * fov_deg * std::numbers::pi / 180.0;
  KannalaBrandtParams p;
  p.width = p.height = size;
  p.fx = p.fy = 0.5 * size / half_fov;  // the image circle's radius, size / 2, is half_fov
  p.cx = p.cy = 0.5 * (size - 1);
  p.max_theta = half_fov;
  return KannalaBrandtCamera(p);
}

std::optional<Eigen::Vector2d> KannalaBrandtCamera::project(const Eigen::Vector3d& p) const {
  const double r = std::hypot(p.x(), p.y());
  const double theta = std::atan2(r, p.z());
  if (!(theta <= p_.max_theta)) return std::nullopt;  // also rejects NaN and the zero vector
  if (r == 0) {
    if (!(p.z() > 0)) return std::nullopt;
    return Eigen::Vector2d(p_.cx, p_.cy);
  }
  const double s = kannala_brandt_distorted_angle(p_.k, theta) / r;
  return Eigen::Vector2d(p_.fx * s * p.x() + p_.cx, p_.fy * s * p.y() + p_.cy);
}

std::optional<Eigen::Vector3d> KannalaBrandtCamera::unproject(const Eigen::Vector2d& pixel) const {
  const double mx = (pixel.x() - p_.cx) / p_.fx, my = (pixel.y() - p_.cy) / p_.fy;
  const double theta_d = std::hypot(mx, my);
  if (!std::isfinite(theta_d)) return std::nullopt;
  if (theta_d == 0) return Eigen::Vector3d(0, 0, 1);
  // The model is valid (and, for sane k, monotonic) only up to max_theta.
  if (theta_d > kannala_brandt_distorted_angle(p_.k, p_.max_theta) * (1 + 1e-12))
    return std::nullopt;

  // Newton on theta_d(theta) - theta_d = 0, as cv::fisheye::undistortPoints does.
  const auto& k = p_.k;
  double theta = theta_d;
  bool converged = false;
  for (int i = 0; i < 20 && !converged; ++i) {
    const double t2 = theta * theta;
    const double f = kannala_brandt_distorted_angle(k, theta) - theta_d;
    const double df = 1.0 + t2 * (3 * k[0] + t2 * (5 * k[1] + t2 * (7 * k[2] + t2 * 9 * k[3])));
    if (!(df > 0)) return std::nullopt;
    const double step = f / df;
    theta -= step;
    converged = std::abs(step) < 1e-14;
  }
  if (!(theta >= 0 && theta <= p_.max_theta * (1 + 1e-12))) return std::nullopt;
  if (std::abs(kannala_brandt_distorted_angle(k, theta) - theta_d) > 1e-10) return std::nullopt;
  const double s = std::sin(theta) / theta_d;
  return Eigen::Vector3d(s * mx, s * my, std::cos(theta));
}

std::unique_ptr<CameraModel> KannalaBrandtCamera::clone() const {
  return std::make_unique<KannalaBrandtCamera>(*this);
}

}  // namespace probeless
