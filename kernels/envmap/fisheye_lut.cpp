#include "kernels/envmap/fisheye_lut.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace probeless::envmap {

namespace {

// Pixels per radian near the axis: how far a milliradian off the axis moves the image point.
double axial_focal_length(const CameraModel& camera) {
  const auto c = camera.project(Eigen::Vector3d(0, 0, 1));
  const auto x = camera.project(Eigen::Vector3d(1e-3, 0, 1));
  const auto y = camera.project(Eigen::Vector3d(0, 1e-3, 1));
  if (!c || !x || !y)
    throw std::invalid_argument("fisheye table: the " + camera.kind() +
                                " model does not project its optical axis");
  return std::max((*x - *c).norm(), (*y - *c).norm()) / 1e-3;
}

// The widest angle from the axis that any pixel of the frame sees: the table needs to reach
// no further. Every 4th pixel and the whole border (where the widest angles are).
double widest_angle(const CameraModel& camera) {
  double widest = 0;
  const auto see = [&](int x, int y) {
    if (const auto ray = camera.unproject(Eigen::Vector2d(x, y)))
      widest = std::max(widest, std::acos(std::clamp(ray->z(), -1.0, 1.0)));
  };
  const int w = camera.width(), h = camera.height();
  for (int y = 0; y < h; y += 4)
    for (int x = 0; x < w; x += 4) see(x, y);
  for (int x = 0; x < w; ++x) see(x, 0), see(x, h - 1);
  for (int y = 0; y < h; ++y) see(0, y), see(w - 1, y);
  return widest;
}

// The widest angle from the axis the model projects at all, the least over eight azimuths
// (bisection: the models' domains are discs around the axis).
double domain_limit(const CameraModel& camera) {
  double limit = std::numbers::pi;
  for (int a = 0; a < 8; ++a) {
    const double phi = a * std::numbers::pi / 4;
    const auto sees = [&](double theta) {
      return camera
          .project(Eigen::Vector3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                   std::cos(theta)))
          .has_value();
    };
    if (sees(std::numbers::pi)) continue;
    double lo = 0, hi = std::numbers::pi;
    for (int i = 0; i < 60; ++i) (sees(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
    limit = std::min(limit, lo);
  }
  return limit;
}

Eigen::Vector3d direction(double theta, double gx, double gy) {
  const double rho = std::hypot(gx, gy);
  const double s = rho > 0 ? std::sin(theta) / rho : 0.0;
  return {s * gx, s * gy, std::cos(theta)};
}

}  // namespace

std::shared_ptr<const FisheyeLut> build_fisheye_lut(const CameraModel& camera, float cell_px) {
  if (!(cell_px > 0.05F && cell_px <= 16.0F))
    throw std::invalid_argument("fisheye table: cell_px must be in (0.05, 16]");
  auto lut = std::make_shared<FisheyeLut>();
  lut->image_width = camera.width();
  lut->image_height = camera.height();
  lut->model = camera.kind();
  const double scale = axial_focal_length(camera) / cell_px;
  const double limit = domain_limit(camera);
  lut->scale = static_cast<float>(scale);
  lut->max_theta = static_cast<float>(limit);
  // Three cells beyond what the frame sees, so that a footprint at the frame's edge has its
  // four corners in the table; never beyond the direction straight back.
  const double reach = std::min(widest_angle(camera), limit);
  const int radius = static_cast<int>(std::ceil(reach * scale)) + 3;
  lut->size = 2 * radius + 1;
  lut->centre = static_cast<float>(radius);
  lut->pixel = Image<float, 2>(lut->size, lut->size);
  // Just inside the domain's edge, and a cell further in: the cells beyond it are extrapolated
  // along their radius, so the last cell inside interpolates towards a sensible corner and the
  // kernel's theta <= max_theta, not the table, decides what is seen (as the analytic
  // Kannala-Brandt kernel did).
  const double edge = limit * (1 - 1e-9), inner = edge - 1 / scale;
  for (int j = 0; j < lut->size; ++j)
    for (int i = 0; i < lut->size; ++i) {
      const double gx = i - radius, gy = j - radius;
      const double theta = std::hypot(gx, gy) / scale;
      std::optional<Eigen::Vector2d> px;
      if (theta <= edge) {
        px = camera.project(direction(theta, gx, gy));
      } else if (theta < std::numbers::pi && theta <= edge + 4 / scale) {
        const auto a = camera.project(direction(edge, gx, gy));
        const auto b = camera.project(direction(inner, gx, gy));
        if (a && b) px = *a + (theta - edge) * scale * (*a - *b);
      }
      lut->pixel.at(i, j, 0) = px ? static_cast<float>(px->x()) : FisheyeLut::kInvalid;
      lut->pixel.at(i, j, 1) = px ? static_cast<float>(px->y()) : FisheyeLut::kInvalid;
    }
  return lut;
}

}  // namespace probeless::envmap
