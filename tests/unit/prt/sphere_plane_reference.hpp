#pragma once
// An independent reference for the PRT bake (issue #6: "PRT of a sphere on a plane against a
// reference computed by brute-force Monte Carlo"): an exact sphere instead of a triangle
// mesh, the analytic ray-sphere intersection instead of the BVH, pseudo-random uniform
// directions on the hemisphere instead of the cosine-weighted Hammersley set, and the
// integral written as it is defined:
//   T_i = 1/pi * integral V max(0, n.w) y_i(w) dw ~ 1/pi * 2 pi / N * sum V (n.w) y_i(w).
// The only shared code is the SH basis (core/sh.hpp), which has its own tests.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>

#include "core/sh.hpp"

namespace probeless::prt::testing {

struct SpherePlaneScene {
  Eigen::Vector3d centre{0, 0, 0.1};
  double radius = 0.1;
  bool plane = true;       // the solid half-space z < 0
  bool mirror = false;     // the sphere reflects rays
  double reflectance = 1;  // per bounce
};

// Distance along the unit ray to the sphere, if it hits it ahead.
inline std::optional<double> hit_sphere(const SpherePlaneScene& s, const Eigen::Vector3d& o,
                                        const Eigen::Vector3d& w) {
  const Eigen::Vector3d oc = o - s.centre;
  const double b = oc.dot(w), c = oc.squaredNorm() - s.radius * s.radius;
  const double disc = b * b - c;
  if (disc < 0) return std::nullopt;
  const double root = std::sqrt(disc);
  if (-b - root > 1e-12) return -b - root;
  if (-b + root > 1e-12) return -b + root;  // starting inside the sphere
  return std::nullopt;
}

// Transfer at a point with unit normal n, from `samples` uniform directions.
inline std::array<double, kShMaxCount> reference_transfer(const SpherePlaneScene& s,
                                                          const Eigen::Vector3d& point,
                                                          const Eigen::Vector3d& n, int samples,
                                                          std::uint64_t seed = 7) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  std::array<double, kShMaxCount> t{};
  // A frame around n by Gram-Schmidt (deliberately not the bake's orthonormal_basis).
  const Eigen::Vector3d helper =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d tx = (helper - helper.dot(n) * n).normalized(), ty = n.cross(tx);
  for (int k = 0; k < samples; ++k) {
    // Uniform on the hemisphere: cos(theta) uniform in [0, 1].
    const double z = uniform(rng), phi = 2 * std::numbers::pi * uniform(rng);
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    const Eigen::Vector3d w = r * std::cos(phi) * tx + r * std::sin(phi) * ty + z * n;
    Eigen::Vector3d o = point, d = w;
    double weight = 1;
    bool escaped = false;
    for (int bounce = 0; bounce < 8; ++bounce) {
      // Downwards means the table: in this scene no ray meets the (convex) sphere first on
      // its way down, since every ray starts on the plane or leaves the sphere's surface.
      if (s.plane && (o.z() < 0 || d.z() < 0)) break;
      const auto t_hit = hit_sphere(s, o, d);
      if (!t_hit) {
        escaped = true;
        break;
      }
      if (!s.mirror) break;
      o += *t_hit * d;
      const Eigen::Vector3d normal = (o - s.centre).normalized();
      d -= 2 * d.dot(normal) * normal;
      o += 1e-9 * normal;
      weight *= s.reflectance;
    }
    if (!escaped) continue;
    const ShBasis y = sh_basis(d);
    for (int i = 0; i < kShMaxCount; ++i) t[i] += weight * z * y[i];
  }
  for (double& v : t) v *= 2.0 / samples;  // (1/pi) (2 pi / N)
  return t;
}

}  // namespace probeless::prt::testing
