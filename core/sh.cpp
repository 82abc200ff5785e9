#include "core/sh.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/latlong.hpp"

namespace probeless {
namespace {

constexpr double kPi = std::numbers::pi;

// Normalisation constants of the real harmonics written as polynomials in x, y, z, from their
// closed forms (for l <= 2 these are R&H 2001's 0.282095, 0.488603, 1.092548, 0.315392,
// 0.546274). Suffix n: the m < 0 partner where it differs from m > 0.
constexpr double k00 = 0.28209479177387814;  // 1/2 sqrt(1/pi)
constexpr double k1 = 0.4886025119029199;    // sqrt(3/(4 pi))
constexpr double k2a = 1.0925484305920792;   // 1/2 sqrt(15/pi): xy, yz, xz
constexpr double k20 = 0.31539156525252005;  // 1/4 sqrt(5/pi): 3z^2 - 1
constexpr double k22 = 0.5462742152960396;   // 1/4 sqrt(15/pi): x^2 - y^2
constexpr double k33 = 0.5900435899266435;   // 1/4 sqrt(35/(2 pi))
constexpr double k32n = 2.890611442640554;   // 1/2 sqrt(105/pi)
constexpr double k31 = 0.4570457994644658;   // 1/4 sqrt(21/(2 pi))
constexpr double k30 = 0.3731763325901154;   // 1/4 sqrt(7/pi)
constexpr double k32 = 1.445305721320277;    // 1/4 sqrt(105/pi)
constexpr double k44n = 2.5033429417967046;  // 3/4 sqrt(35/pi)
constexpr double k43 = 1.7701307697799304;   // 3/4 sqrt(35/(2 pi))
constexpr double k42n = 0.9461746957575601;  // 3/4 sqrt(5/pi)
constexpr double k41 = 0.6690465435572892;   // 3/4 sqrt(5/(2 pi))
constexpr double k40 = 0.10578554691520431;  // 3/16 sqrt(1/pi)
constexpr double k42 = 0.47308734787878004;  // 3/8 sqrt(5/pi)
constexpr double k44 = 0.6258357354491761;   // 3/16 sqrt(35/pi)

void check_bands(int bands) {
  if (bands < 1 || bands > kShMaxBands) throw std::invalid_argument("SH: bands must be 1..5");
}

// Adds value * Y(direction) * weight to the first bands^2 coefficients.
void accumulate(ShRgb& sh, const Eigen::Vector3d& direction, const Eigen::Vector3d& value,
                double weight) {
  const ShBasis y = sh_basis(direction);
  for (std::size_t i = 0; i < static_cast<std::size_t>(sh.count()); ++i)
    sh.c[i] += value * (y[i] * weight);
}

Eigen::Vector3d rgb(const ImageRGBF& img, int x, int y) {
  return {img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)};
}

}  // namespace

ShBasis sh_basis(const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = direction.normalized();
  const double x = d.x(), y = d.y(), z = d.z();
  const double x2 = x * x, y2 = y * y, z2 = z * z;
  return {
      k00,                                              // 0,0
      k1 * y,                                           // 1,-1
      k1 * z,                                           // 1,0
      k1 * x,                                           // 1,1
      k2a * x * y,                                      // 2,-2
      k2a * y * z,                                      // 2,-1
      k20 * (3 * z2 - 1),                               // 2,0
      k2a * x * z,                                      // 2,1
      k22 * (x2 - y2),                                  // 2,2
      k33 * y * (3 * x2 - y2),                          // 3,-3
      k32n * x * y * z,                                 // 3,-2
      k31 * y * (5 * z2 - 1),                           // 3,-1
      k30 * z * (5 * z2 - 3),                           // 3,0
      k31 * x * (5 * z2 - 1),                           // 3,1
      k32 * z * (x2 - y2),                              // 3,2
      k33 * x * (x2 - 3 * y2),                          // 3,3
      k44n * x * y * (x2 - y2),                         // 4,-4
      k43 * y * z * (3 * x2 - y2),                      // 4,-3
      k42n * x * y * (7 * z2 - 1),                      // 4,-2
      k41 * y * z * (7 * z2 - 3),                       // 4,-1
      k40 * (35 * z2 * z2 - 30 * z2 + 3),               // 4,0
      k41 * x * z * (7 * z2 - 3),                       // 4,1
      k42 * (x2 - y2) * (7 * z2 - 1),                   // 4,2
      k43 * x * z * (x2 - 3 * y2),                      // 4,3
      k44 * (x2 * (x2 - 3 * y2) - y2 * (3 * x2 - y2)),  // 4,4
  };
}

Eigen::Vector3d ShRgb::evaluate(const Eigen::Vector3d& direction) const {
  const ShBasis y = sh_basis(direction);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < static_cast<std::size_t>(count()); ++i) sum += c[i] * y[i];
  return sum;
}

ShRgb project_sh(const Cubemap& cubemap, int bands) {
  check_bands(bands);
  ShRgb sh;
  sh.bands = bands;
  const int n = cubemap.face_size;
  for (int f = 0; f < 6; ++f) {
    const ImageRGBF& face = cubemap.faces[static_cast<std::size_t>(f)];
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        accumulate(sh, cube_direction(static_cast<CubeFace>(f), (x + 0.5) / n, (y + 0.5) / n),
                   rgb(face, x, y), cube_texel_solid_angle(x, y, n));
  }
  return sh;
}

ShRgb project_sh_latlong(const ImageRGBF& latlong, int bands) {
  check_bands(bands);
  ShRgb sh;
  sh.bands = bands;
  const int w = latlong.width(), h = latlong.height();
  for (int y = 0; y < h; ++y) {
    const double solid_angle = latlong_pixel_solid_angle(y, w, h);
    for (int x = 0; x < w; ++x)
      accumulate(sh, latlong_pixel_direction(x, y, w, h), rgb(latlong, x, y), solid_angle);
  }
  return sh;
}

Eigen::Vector3d sh_irradiance(const ShRgb& radiance, const Eigen::Vector3d& normal) {
  if (radiance.bands < 3) throw std::invalid_argument("sh_irradiance: needs 3 bands");
  constexpr double c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
  const Eigen::Vector3d n = normal.normalized();
  const double x = n.x(), y = n.y(), z = n.z();
  const auto& L = radiance.c;
  return c1 * L[sh_index(2, 2)] * (x * x - y * y) + c3 * L[sh_index(2, 0)] * (z * z) + c4 * L[0] -
         c5 * L[sh_index(2, 0)] +
         2 * c1 *
             (L[sh_index(2, -2)] * (x * y) + L[sh_index(2, 1)] * (x * z) +
              L[sh_index(2, -1)] * (y * z)) +
         2 * c2 * (L[sh_index(1, 1)] * x + L[sh_index(1, -1)] * y + L[sh_index(1, 0)] * z);
}

namespace {

// Each band is closed under rotation, so its rotation matrix follows exactly from samples:
// with A the band's basis at directions d_k and B at R^T d_k, g = A c' = B c, hence
// c' = A^+ B c. The directions and the pseudo-inverses A^+ do not depend on R and are made
// once, so a rotation costs 64 basis evaluations and four small products (a few
// microseconds), cheap enough per object per frame.
struct RotationFit {
  static constexpr int kCount = 64;  // spherical Fibonacci points: well spread, no symmetry
  std::array<Eigen::Vector3d, kCount> directions;
  std::array<Eigen::MatrixXd, kShMaxBands> pinv;  // band l: (2l+1) x kCount

  RotationFit() {
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    Eigen::MatrixXd A(kCount, kShMaxCount);
    for (int k = 0; k < kCount; ++k) {
      const double z = 1.0 - (2.0 * k + 1.0) / kCount, r = std::sqrt(1.0 - z * z);
      directions[static_cast<std::size_t>(k)] = {r * std::cos(golden * k), r * std::sin(golden * k),
                                                 z};
      const ShBasis y = sh_basis(directions[static_cast<std::size_t>(k)]);
      for (int i = 0; i < kShMaxCount; ++i) A(k, i) = y[static_cast<std::size_t>(i)];
    }
    for (int l = 0; l < kShMaxBands; ++l) {
      const Eigen::MatrixXd a = A.middleCols(l * l, 2 * l + 1);
      pinv[static_cast<std::size_t>(l)] =
          a.colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(kCount, kCount));
    }
  }
};

}  // namespace

ShRotation sh_rotation(const Eigen::Matrix3d& rotation) {
  static const RotationFit fit;
  Eigen::MatrixXd B(RotationFit::kCount, kShMaxCount);
  for (int k = 0; k < RotationFit::kCount; ++k) {
    const ShBasis b = sh_basis(rotation.transpose() * fit.directions[static_cast<std::size_t>(k)]);
    for (int i = 0; i < kShMaxCount; ++i) B(k, i) = b[static_cast<std::size_t>(i)];
  }
  ShRotation m = ShRotation::Zero();
  m(0, 0) = 1.0;  // band 0 is a constant
  for (int l = 1; l < kShMaxBands; ++l) {
    const int first = l * l, size = 2 * l + 1;
    m.block(first, first, size, size) =
        fit.pinv[static_cast<std::size_t>(l)] * B.middleCols(first, size);
  }
  return m;
}

ShRgb apply_sh_rotation(const ShRgb& sh, const ShRotation& rotation) {
  ShRgb out = sh;
  for (int l = 0; l < sh.bands; ++l) {  // block-diagonal: bands do not mix
    const int first = l * l, end = (l + 1) * (l + 1);
    for (int i = first; i < end; ++i) {
      Eigen::Vector3d v = Eigen::Vector3d::Zero();
      for (int j = first; j < end; ++j) v += rotation(i, j) * sh.c[static_cast<std::size_t>(j)];
      out.c[static_cast<std::size_t>(i)] = v;
    }
  }
  return out;
}

ShRgb rotate_sh(const ShRgb& sh, const Eigen::Matrix3d& rotation) {
  return apply_sh_rotation(sh, sh_rotation(rotation));
}

}  // namespace probeless
