#include "core/camera/pinhole.hpp"

#include <cmath>
#include <limits>

namespace probeless {

namespace {

// Brown-Conrady distortion of normalised coordinates, OpenCV's formula (calib3d,
// "Camera Calibration and 3D Reconstruction").
Eigen::Vector2d distort(const BrownDistortion& d, const Eigen::Vector2d& m) {
  const double x = m.x(), y = m.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  return {x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x),
          y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y};
}

// The radius (normalised) up to which r * radial(r) keeps increasing. Beyond it a polynomial
// with negative k folds back and would map points far outside the field of view into the
// image, so the model treats those directions as unseen. Searched out to r = 20 (87 deg).
double monotone_radius(const BrownDistortion& d) {
  if (d.k1 >= 0 && d.k2 >= 0 && d.k3 >= 0) return std::numeric_limits<double>::infinity();
  auto slope = [&](double r) {  // d/dr of r (1 + k1 r^2 + k2 r^4 + k3 r^6)
    const double r2 = r * r;
    return 1.0 + r2 * (3.0 * d.k1 + r2 * (5.0 * d.k2 + r2 * 7.0 * d.k3));
  };
  constexpr double kLimit = 20.0, kStep = 1e-3;
  double r = 0;
  while (r < kLimit && slope(r + kStep) > 0) r += kStep;
  if (r >= kLimit) return std::numeric_limits<double>::infinity();
  double lo = r, hi = r + kStep;  // bisect the sign change
  for (int i = 0; i < 60; ++i) (slope(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  return lo;
}

}  // namespace

PinholeCamera::PinholeCamera(PinholeIntrinsics k, BrownDistortion d)
    : k_(k), d_(d), max_radius_(monotone_radius(d)) {}

std::optional<Eigen::Vector2d> PinholeCamera::project(const Eigen::Vector3d& p) const {
  if (!(p.z() > 0)) return std::nullopt;
  Eigen::Vector2d m(p.x() / p.z(), p.y() / p.z());
  if (!d_.is_zero()) {
    if (m.norm() > max_radius_) return std::nullopt;
    m = distort(d_, m);
  }
  return Eigen::Vector2d(k_.fx * m.x() + k_.cx, k_.fy * m.y() + k_.cy);
}

std::optional<Eigen::Vector3d> PinholeCamera::unproject(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d md((pixel.x() - k_.cx) / k_.fx, (pixel.y() - k_.cy) / k_.fy);
  Eigen::Vector2d m = md;
  if (!d_.is_zero()) {
    // OpenCV's undistortPoints iteration: m = (md - tangential(m)) / radial(m).
    for (int i = 0; i < 100; ++i) {
      const double x = m.x(), y = m.y();
      const double r2 = x * x + y * y;
      const double radial = 1.0 + r2 * (d_.k1 + r2 * (d_.k2 + r2 * d_.k3));
      const Eigen::Vector2d tangential(2.0 * d_.p1 * x * y + d_.p2 * (r2 + 2.0 * x * x),
                                       d_.p1 * (r2 + 2.0 * y * y) + 2.0 * d_.p2 * x * y);
      if (!(radial > 0)) return std::nullopt;
      const Eigen::Vector2d next = (md - tangential) / radial;
      const double step = (next - m).squaredNorm();
      m = next;
      if (step < 1e-28) break;
    }
    // The iteration diverges or lands on the folded branch for pixels the lens never maps.
    if (!m.allFinite() || m.norm() > max_radius_) return std::nullopt;
    const Eigen::Vector2d back = distort(d_, m);
    const double err_px = std::hypot((back.x() - md.x()) * k_.fx, (back.y() - md.y()) * k_.fy);
    if (!(err_px < 1e-6)) return std::nullopt;
  }
  return Eigen::Vector3d(m.x(), m.y(), 1.0).normalized();
}

std::unique_ptr<CameraModel> PinholeCamera::clone() const {
  return std::make_unique<PinholeCamera>(*this);
}

Eigen::Matrix3d PinholeCamera::matrix() const {
  Eigen::Matrix3d K;
  K << k_.fx, 0, k_.cx, 0, k_.fy, k_.cy, 0, 0, 1;
  return K;
}

}  // namespace probeless
