#include "core/latlong.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace probeless {
namespace {

constexpr double kPi = std::numbers::pi;

// Bilinear weights between texel centres along one axis of n texels; `wrap` for azimuth.
struct Tap {
  int i0, i1;
  float w1;
};
Tap tap(double coord, int n, bool wrap) {
  const double f = coord * n - 0.5;
  const double fl = std::floor(f);
  int i0 = static_cast<int>(fl), i1 = i0 + 1;
  const auto w1 = static_cast<float>(f - fl);
  if (wrap) {
    i0 = ((i0 % n) + n) % n;
    i1 = ((i1 % n) + n) % n;
  } else {
    i0 = std::clamp(i0, 0, n - 1);
    i1 = std::clamp(i1, 0, n - 1);
  }
  return {i0, i1, w1};
}

Eigen::Vector3f bilinear(const ImageRGBF& img, const Tap& tx, const Tap& ty) {
  auto px = [&](int x, int y) {
    return Eigen::Vector3f(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2));
  };
  const Eigen::Vector3f top = (1 - tx.w1) * px(tx.i0, ty.i0) + tx.w1 * px(tx.i1, ty.i0);
  const Eigen::Vector3f bottom = (1 - tx.w1) * px(tx.i0, ty.i1) + tx.w1 * px(tx.i1, ty.i1);
  return (1 - ty.w1) * top + ty.w1 * bottom;
}

// Bilinear within the face the direction falls on, clamped at the face's edges.
Eigen::Vector3f sample_cubemap_bilinear(const Cubemap& cube, const Eigen::Vector3d& direction) {
  const CubeTexel t = cube_texel_from_direction(direction);
  return bilinear(cube.face(t.face), tap(t.u, cube.face_size, false),
                  tap(t.v, cube.face_size, false));
}

void check_supersample(int supersample) {
  if (supersample < 1 || supersample > 16)
    throw std::invalid_argument("latlong: supersample must be 1..16");
}

}  // namespace

Eigen::Vector3d latlong_direction(double u, double v) {
  const double azimuth = kPi * (2.0 * u - 1.0), polar = kPi * v;
  const double s = std::sin(polar);
  return {s * std::sin(azimuth), -s * std::cos(azimuth), std::cos(polar)};
}

Eigen::Vector2d latlong_uv(const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = direction.normalized();
  double u = 0.5 * (1.0 + std::atan2(d.x(), -d.y()) / kPi);
  if (u >= 1.0) u = 0.0;  // atan2 gives +pi on the seam; keep u in [0, 1)
  return {u, std::acos(std::clamp(d.z(), -1.0, 1.0)) / kPi};
}

Eigen::Vector3d latlong_pixel_direction(int x, int y, int width, int height) {
  return latlong_direction((x + 0.5) / width, (y + 0.5) / height);
}

double latlong_pixel_solid_angle(int y, int width, int height) {
  return (std::cos(kPi * y / height) - std::cos(kPi * (y + 1) / height)) * 2.0 * kPi / width;
}

Eigen::Vector3f sample_latlong(const ImageRGBF& latlong, const Eigen::Vector3d& direction) {
  const Eigen::Vector2d uv = latlong_uv(direction);
  return bilinear(latlong, tap(uv.x(), latlong.width(), true),
                  tap(uv.y(), latlong.height(), false));
}

Cubemap cubemap_from_latlong(const ImageRGBF& latlong, int face_size, int supersample) {
  check_supersample(supersample);
  if (latlong.empty() || face_size <= 0)
    throw std::invalid_argument("cubemap_from_latlong: empty input or face size");
  Cubemap cube(face_size);
  const double step = 1.0 / (face_size * supersample);
  const float norm = 1.0f / static_cast<float>(supersample * supersample);
  for (int f = 0; f < 6; ++f) {
    ImageRGBF& face = cube.faces[static_cast<std::size_t>(f)];
    for (int y = 0; y < face_size; ++y)
      for (int x = 0; x < face_size; ++x) {
        Eigen::Vector3f sum = Eigen::Vector3f::Zero();
        for (int sy = 0; sy < supersample; ++sy)
          for (int sx = 0; sx < supersample; ++sx) {
            const double u = (x * supersample + sx + 0.5) * step;
            const double v = (y * supersample + sy + 0.5) * step;
            sum += sample_latlong(latlong, cube_direction(static_cast<CubeFace>(f), u, v));
          }
        for (int c = 0; c < 3; ++c) face.at(x, y, c) = sum[c] * norm;
      }
  }
  return cube;
}

ImageRGBF latlong_from_cubemap(const Cubemap& cubemap, int width, int height, int supersample) {
  check_supersample(supersample);
  if (cubemap.face_size <= 0 || width <= 0 || height <= 0)
    throw std::invalid_argument("latlong_from_cubemap: empty input or output size");
  ImageRGBF out(width, height);
  const float norm = 1.0f / static_cast<float>(supersample * supersample);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      for (int sy = 0; sy < supersample; ++sy)
        for (int sx = 0; sx < supersample; ++sx) {
          const double u = (x + (sx + 0.5) / supersample) / width;
          const double v = (y + (sy + 0.5) / supersample) / height;
          sum += sample_cubemap_bilinear(cubemap, latlong_direction(u, v));
        }
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = sum[c] * norm;
    }
  return out;
}

}  // namespace probeless
