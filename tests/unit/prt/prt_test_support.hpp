#pragma once
// Shared pieces of the PRT tests: the scenes and the analytic unshadowed transfer.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <numbers>

#include "app/render/mesh.hpp"
#include "app/render/prt/prt.hpp"
#include "core/sh.hpp"
#include "core/sphere_sampling.hpp"

namespace probeless::prt::testing {

constexpr double kPi = std::numbers::pi;
// T_0 of a vertex that sees its whole hemisphere: y_0 = 1 / (2 sqrt(pi)).
constexpr double kOpenT0 = 0.28209479177387814;

// Funk-Hecke coefficients of the clamped cosine max(0, cos theta) (Ramamoorthi & Hanrahan
// 2001, "An Efficient Representation for Irradiance Environment Maps", eq. 8): A_0 = pi,
// A_1 = 2 pi / 3, A_2 = pi / 4, A_3 = 0, A_4 = -pi / 24.
constexpr std::array<double, 5> kClampedCosineA{kPi, 2 * kPi / 3, kPi / 4, 0, -kPi / 24};

// The transfer of an unoccluded vertex with unit normal n, built as the zonal clamped cosine
// about +z (coefficient A_l / pi * y_l0(+z), y_l0(+z) = sqrt((2l + 1) / (4 pi))) turned by
// the rotation taking +z to n (core's rotate_sh: g(d) = f(R^T d) = max(0, n.d) / pi).
inline std::array<double, kShMaxCount> open_transfer(const Eigen::Vector3d& n) {
  ShRgb zonal;
  for (int l = 0; l < 5; ++l)
    zonal.c[sh_index(l, 0)] =
        Eigen::Vector3d::Constant(kClampedCosineA[l] / kPi * std::sqrt((2 * l + 1) / (4 * kPi)));
  const ShRgb turned = rotate_sh(zonal, orthonormal_basis(n.normalized()));
  std::array<double, kShMaxCount> t{};
  for (int i = 0; i < kShMaxCount; ++i) t[i] = turned.c[i].x();
  return t;
}

// The built-in sphere (radius 0.1) resting on the plane z = 0.
inline render::Mesh sphere_on_floor(int segments = 48, int rings = 24) {
  render::Mesh m = render::make_sphere(0.1f, segments, rings);
  for (auto& p : m.positions) p.z() += 0.1f;
  return m;
}

inline Ground floor_ground() {
  return Ground{};  // z = 0, normal +z, default grid
}

// Largest absolute difference over the 25 coefficients.
template <typename A, typename B>
double max_abs_diff(const A& a, const B& b) {
  double m = 0;
  for (int i = 0; i < kShMaxCount; ++i)
    m = std::max(m, std::abs(static_cast<double>(a[i]) - static_cast<double>(b[i])));
  return m;
}

}  // namespace probeless::prt::testing
