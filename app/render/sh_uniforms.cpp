#include "app/render/sh_uniforms.hpp"

#include <stdexcept>

namespace probeless::render {

std::array<Eigen::Matrix4f, 3> irradiance_matrices(const ShRgb& radiance) {
  if (radiance.bands < 3) throw std::invalid_argument("irradiance_matrices: needs 3 bands");
  constexpr double c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
  std::array<Eigen::Matrix4f, 3> out;
  for (int ch = 0; ch < 3; ++ch) {
    auto L = [&](int l, int m) { return radiance.c[static_cast<std::size_t>(sh_index(l, m))][ch]; };
    Eigen::Matrix4d m;
    m << c1 * L(2, 2), c1 * L(2, -2), c1 * L(2, 1), c2 * L(1, 1),    //
        c1 * L(2, -2), -c1 * L(2, 2), c1 * L(2, -1), c2 * L(1, -1),  //
        c1 * L(2, 1), c1 * L(2, -1), c3 * L(2, 0), c2 * L(1, 0),     //
        c2 * L(1, 1), c2 * L(1, -1), c2 * L(1, 0), c4 * L(0, 0) - c5 * L(2, 0);
    out[static_cast<std::size_t>(ch)] = m.cast<float>();
  }
  return out;
}

std::array<float, 84> prt_light(const ShRgb& radiance_world,
                                const Eigen::Matrix3d& R_world_object) {
  ShRgb full = radiance_world;
  full.bands = kShMaxBands;  // entries past the given bands are zero (ShRgb's contract)
  const ShRgb object = rotate_sh(full, Eigen::Matrix3d(R_world_object.transpose()));
  std::array<float, 84> packed{};
  for (int ch = 0; ch < 3; ++ch)
    for (int i = 0; i < kShMaxCount; ++i)
      packed[static_cast<std::size_t>(28 * ch + i)] =
          static_cast<float>(object.c[static_cast<std::size_t>(i)][ch]);
  return packed;
}

}  // namespace probeless::render
