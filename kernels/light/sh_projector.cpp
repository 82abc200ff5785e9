#include "kernels/light/sh_projector.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace probeless::light {

ShProjector::ShProjector(int face_size, int bands) : face_size_(face_size), bands_(bands) {
  if (face_size < 1 || bands < 1 || bands > kShMaxBands)
    throw std::invalid_argument("ShProjector: face size >= 1, bands 1..5");
  const int m = face_size, count = bands * bands;
  table_.resize(static_cast<std::size_t>(6 * m * m * count));
  std::size_t i = 0;
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < m; ++y)
      for (int x = 0; x < m; ++x) {
        const ShBasis b =
            sh_basis(cube_direction(static_cast<CubeFace>(f), (x + 0.5) / m, (y + 0.5) / m));
        const double w = cube_texel_solid_angle(x, y, m);
        for (int k = 0; k < count; ++k) table_[i++] = static_cast<float>(b[k] * w);
      }
}

ShProjector::ShProjector(int face_size, const envmap::ParallaxConstants& reprojection, int samples,
                         int bands)
    : face_size_(face_size), bands_(bands) {
  if (face_size < 1 || bands < 1 || bands > kShMaxBands || samples < 1)
    throw std::invalid_argument("ShProjector: face size >= 1, bands 1..5, samples >= 1");
  const int m = face_size, count = bands * bands;
  table_.assign(static_cast<std::size_t>(6 * m * m * count), 0.0F);
  const double per_sample = 1.0 / (samples * samples);
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < m; ++y)
      for (int x = 0; x < m; ++x) {
        const ShBasis b =
            sh_basis(cube_direction(static_cast<CubeFace>(f), (x + 0.5) / m, (y + 0.5) / m));
        const double w = cube_texel_solid_angle(x, y, m) * per_sample;
        for (int j = 0; j < samples; ++j)
          for (int i = 0; i < samples; ++i) {
            const float u = (static_cast<float>(x * samples + i) + 0.5F) / (m * samples);
            const float v = (static_cast<float>(y * samples + j) + 0.5F) / (m * samples);
            const envmap::CubeCoord cc = envmap::cube_coord_of(
                envmap::parallax_direction(reprojection, envmap::cube_face_direction(f, u, v)));
            const float px = cc.u * static_cast<float>(m) - 0.5F;
            const float py = cc.v * static_cast<float>(m) - 0.5F;
            const float x0f = std::floor(px), y0f = std::floor(py);
            const double ax = px - x0f, ay = py - y0f;
            const auto add = [&](float xf, float yf, double weight) {
              const int xi = std::clamp(static_cast<int>(xf), 0, m - 1);
              const int yi = std::clamp(static_cast<int>(yf), 0, m - 1);
              float* t = &table_[static_cast<std::size_t>(((cc.face * m + yi) * m + xi) * count)];
              for (int k = 0; k < count; ++k) t[k] += static_cast<float>(b[k] * w * weight);
            };
            add(x0f, y0f, (1 - ax) * (1 - ay));
            add(x0f + 1, y0f, ax * (1 - ay));
            add(x0f, y0f + 1, (1 - ax) * ay);
            add(x0f + 1, y0f + 1, ax * ay);
          }
      }
}

ShRgb ShProjector::project(const envmap::ImageRGBAF& faces) const {
  const int m = face_size_, count = bands_ * bands_;
  if (faces.width() != m || faces.height() != 6 * m)
    throw std::invalid_argument("ShProjector: cubemap size differs from the table's");
  // Float accumulation per coefficient over at most 6 x 64 x 64 texels is good to ~1e-6
  // relative; double sums at the end.
  std::array<std::array<float, 3>, kShMaxCount> acc{};
  const float* px = faces.data();
  const float* w = table_.data();
  for (std::size_t t = 0; t < faces.pixel_count(); ++t, px += 4, w += count)
    for (int k = 0; k < count; ++k) {
      acc[k][0] += w[k] * px[0];
      acc[k][1] += w[k] * px[1];
      acc[k][2] += w[k] * px[2];
    }
  ShRgb out;
  out.bands = bands_;
  for (int k = 0; k < count; ++k) out.c[k] = Eigen::Vector3d(acc[k][0], acc[k][1], acc[k][2]);
  return out;
}

}  // namespace probeless::light
