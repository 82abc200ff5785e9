#pragma once
// Real spherical harmonics up to 5 bands (l = 0..4, 25 coefficients), orthonormal over the
// sphere, with Ramamoorthi & Hanrahan's (2001) signs: no Condon-Shortley phase, so Y1,1 is
// +0.488603 x. Coefficient i = l (l + 1) + m, m from -l to l:
//   L00, L1-1 (y), L10 (z), L11 (x), L2-2 (xy), L2-1 (yz), L20, L21 (xz), L22 (x^2 - y^2), ...
// Directions are in the frame of the map they come from (the world frame, z up, for cubemaps
// and lat-long maps). The thesis lights shadowed diffuse PRT with all 5 bands and unshadowed
// diffuse with the first 3 (9 coefficients) through R&H's irradiance formula.
// docs/lighting-math.md gives the polynomials, the normalisation and the checks.
#include <Eigen/Core>
#include <array>

#include "core/cubemap.hpp"
#include "core/image.hpp"

namespace probeless {

inline constexpr int kShMaxBands = 5;
inline constexpr int kShMaxCount = kShMaxBands * kShMaxBands;  // 25

constexpr int sh_index(int l, int m) {
  return l * (l + 1) + m;
}

using ShBasis = std::array<double, kShMaxCount>;
// All 25 basis functions at a direction (normalised here; it need not be unit).
ShBasis sh_basis(const Eigen::Vector3d& direction);

// RGB coefficients of `bands` bands; the entries past bands^2 are zero.
struct ShRgb {
  int bands = kShMaxBands;
  std::array<Eigen::Vector3d, kShMaxCount> c = zero_coefficients();

  int count() const { return bands * bands; }
  // The band-limited function at a direction.
  Eigen::Vector3d evaluate(const Eigen::Vector3d& direction) const;
  bool operator==(const ShRgb&) const = default;

 private:
  static std::array<Eigen::Vector3d, kShMaxCount> zero_coefficients() {
    std::array<Eigen::Vector3d, kShMaxCount> z;
    z.fill(Eigen::Vector3d::Zero());
    return z;
  }
};

// Projection integrals, sum of L(d) Y(d) dOmega over the texels: exact texel solid angles for
// a cubemap (cube_texel_solid_angle), exact per-row solid angles for a lat-long map.
ShRgb project_sh(const Cubemap& cubemap, int bands = kShMaxBands);
ShRgb project_sh_latlong(const ImageRGBF& latlong, int bands = kShMaxBands);

// Irradiance E(n) at a surface with unit normal n from the first 9 radiance coefficients,
// Ramamoorthi & Hanrahan 2001, eq. 13 (c1..c5 = 0.429043 0.511664 0.743125 0.886227 0.247708).
// A Lambertian surface of albedo rho reflects rho E / pi.
Eigen::Vector3d sh_irradiance(const ShRgb& radiance, const Eigen::Vector3d& normal);

// The linear map on the 25 coefficients that rotates a function by R: block-diagonal, one
// (2l+1)^2 block per band (each band is closed under rotation), and orthogonal.
using ShRotation = Eigen::Matrix<double, kShMaxCount, kShMaxCount>;
ShRotation sh_rotation(const Eigen::Matrix3d& rotation);

// Coefficients of the rotated function g(d) = f(R^T d): what f looks like after turning it by
// R (for example from the world frame into an object's frame, R = R_object_world). The
// matrix form is for applying one rotation to many coefficient sets.
ShRgb rotate_sh(const ShRgb& sh, const Eigen::Matrix3d& rotation);
ShRgb apply_sh_rotation(const ShRgb& sh, const ShRotation& rotation);

}  // namespace probeless
