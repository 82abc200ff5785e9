#include "core/sphere_sampling.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace probeless {
namespace {

constexpr double kPi = std::numbers::pi;

double radical_inverse_base2(std::uint32_t i) {
  // Reverses the bits: i = sum b_k 2^k becomes sum b_k 2^(-k-1).
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
  i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
  i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
  i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
  return static_cast<double>(i) * 0x1p-32;
}

double wrap01(double x) {
  return x - std::floor(x);
}

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

Eigen::Vector2d hammersley(std::uint32_t i, std::uint32_t n, const Eigen::Vector2d& offset) {
  if (i >= n) throw std::invalid_argument("hammersley: index must be below the set size");
  return {wrap01((i + 0.5) / n + offset.x()), wrap01(radical_inverse_base2(i) + offset.y())};
}

Eigen::Vector2d seeded_offset(std::uint64_t seed) {
  std::uint64_t state = seed;
  const double a = static_cast<double>(splitmix64(state) >> 11) * 0x1p-53;
  const double b = static_cast<double>(splitmix64(state) >> 11) * 0x1p-53;
  return {a, b};
}

Eigen::Vector3d cosine_hemisphere(const Eigen::Vector2d& u) {
  // Concentric map: squares around the centre go to circles, each wedge of a square ring to
  // the same wedge of the annulus.
  const double a = 2 * u.x() - 1, b = 2 * u.y() - 1;
  double r = 0, phi = 0;
  if (a == 0 && b == 0) {
    r = 0;
  } else if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = kPi / 4 * (b / a);
  } else {
    r = b;
    phi = kPi / 2 - kPi / 4 * (a / b);
  }
  const double x = r * std::cos(phi), y = r * std::sin(phi);
  // Malley: a uniform point of the disk projected up onto the hemisphere has density cos/pi.
  return {x, y, std::sqrt(std::max(0.0, 1 - x * x - y * y))};
}

std::vector<Eigen::Vector3d> cosine_hemisphere_set(std::uint32_t n, std::uint64_t seed) {
  const Eigen::Vector2d offset = seeded_offset(seed);
  std::vector<Eigen::Vector3d> directions;
  directions.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i)
    directions.push_back(cosine_hemisphere(hammersley(i, n, offset)).normalized());
  return directions;
}

Eigen::Matrix3d orthonormal_basis(const Eigen::Vector3d& normal) {
  const double sign = std::copysign(1.0, normal.z());
  const double a = -1.0 / (sign + normal.z());
  const double b = normal.x() * normal.y() * a;
  Eigen::Matrix3d m;
  m.col(0) << 1 + sign * normal.x() * normal.x() * a, sign * b, -sign * normal.x();
  m.col(1) << b, sign + normal.y() * normal.y() * a, -normal.y();
  m.col(2) = normal;
  return m;
}

}  // namespace probeless
