#include "app/render/environment.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace probeless::render {

void Environment::validate() const {
  const int n = faces.width();
  if (n < 1 || faces.height() != 6 * n)
    throw std::invalid_argument("environment: faces must be n x 6n, got " +
                                std::to_string(faces.width()) + "x" +
                                std::to_string(faces.height()));
  for (std::size_t i = 0; i < faces.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = faces.data()[4 * i + static_cast<std::size_t>(c)];
      if (!std::isfinite(v))
        throw std::invalid_argument("environment: radiance must be finite, texel " +
                                    std::to_string(i) + " has " + std::to_string(v));
    }
  if (sh.bands < 3) throw std::invalid_argument("environment: SH need at least 3 bands");
}

Environment make_environment(ImageRGBAF faces, const ShRgb& sh) {
  Environment e{std::move(faces), sh, {}};
  e.validate();
  return e;
}

Environment make_environment(const Cubemap& radiance, const ShRgb& sh) {
  const int n = radiance.face_size;
  ImageRGBAF faces(n, 6 * n, 1.f);
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        for (int c = 0; c < 3; ++c)
          faces.at(x, f * n + y, c) = radiance.faces[static_cast<std::size_t>(f)].at(x, y, c);
  return make_environment(std::move(faces), sh);
}

Environment make_environment(const Cubemap& radiance) {
  return make_environment(radiance, project_sh(radiance));
}

Cubemap to_cubemap(const Environment& environment) {
  const int n = environment.face_size();
  Cubemap cube(n);
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        for (int c = 0; c < 3; ++c)
          cube.faces[static_cast<std::size_t>(f)].at(x, y, c) =
              environment.faces.at(x, f * n + y, c);
  return cube;
}

}  // namespace probeless::render
