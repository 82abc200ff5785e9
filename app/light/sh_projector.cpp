#include "app/light/sh_projector.hpp"

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
