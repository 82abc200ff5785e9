// The split-sum table (Karis 2013) against its closed form at roughness 0 and an independent
// quadrature of the GGX BRDF over the hemisphere; the SH uniforms of the diffuse materials
// against core's SH functions.
#include "app/render/split_sum.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>

#include "app/render/sh_uniforms.hpp"

namespace probeless::render {
namespace {

constexpr double kPi = std::numbers::pi;

// A mirror (alpha = 0) reflects everything: A + B = 1, and B is Schlick's (1 - n.v)^5.
TEST(SplitSum, MirrorLimitIsExact) {
  for (float n_dot_v : {0.1f, 0.5f, 0.9f, 1.f}) {
    const Eigen::Vector2f ab = integrate_split_sum(n_dot_v, 0.f);
    EXPECT_NEAR(ab.x() + ab.y(), 1.f, 1e-5) << n_dot_v;
    EXPECT_NEAR(ab.y(), std::pow(1.f - n_dot_v, 5.f), 1e-5) << n_dot_v;
  }
}

// A + B and B by midpoint quadrature over the hemisphere of the BRDF
// f = D G F / (4 n.l n.v) times n.l, with F = 1 and F = Schlick's (1 - v.h)^5 part.
Eigen::Vector2d quadrature(double n_dot_v, double roughness) {
  const double alpha = roughness * roughness, a2 = alpha * alpha, k = alpha / 2;
  auto g1 = [&](double c) { return c / (c * (1 - k) + k); };
  const Eigen::Vector3d v(std::sqrt(1 - n_dot_v * n_dot_v), 0, n_dot_v);
  constexpr int kTheta = 600, kPhi = 600;
  double sum = 0, bias = 0;
  for (int i = 0; i < kTheta; ++i) {
    const double theta = (i + 0.5) * (kPi / 2) / kTheta;
    for (int j = 0; j < kPhi; ++j) {
      const double phi = (j + 0.5) * 2 * kPi / kPhi;
      const Eigen::Vector3d l(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                              std::cos(theta));
      const Eigen::Vector3d h = (l + v).normalized();
      const double d = h.z() * h.z() * (a2 - 1) + 1;
      const double D = a2 / (kPi * d * d);
      const double f = D * g1(n_dot_v) * g1(l.z()) / (4 * l.z() * n_dot_v) * l.z();
      const double dw = std::sin(theta) * (kPi / 2 / kTheta) * (2 * kPi / kPhi);
      sum += f * dw;
      bias += f * std::pow(1 - v.dot(h), 5) * dw;
    }
  }
  return {sum, bias};
}

TEST(SplitSum, MatchesQuadratureOfTheBrdf) {
  for (double roughness : {0.4, 0.7, 1.0})
    for (double n_dot_v : {0.25, 0.6, 0.95}) {
      const Eigen::Vector2f ab =
          integrate_split_sum(static_cast<float>(n_dot_v), static_cast<float>(roughness), 2048);
      const Eigen::Vector2d q = quadrature(n_dot_v, roughness);
      EXPECT_NEAR(ab.x() + ab.y(), q.x(), 0.01) << "roughness " << roughness << " n.v " << n_dot_v;
      EXPECT_NEAR(ab.y(), q.y(), 0.005) << "roughness " << roughness << " n.v " << n_dot_v;
    }
}

TEST(SplitSum, TableInterpolatesTheIntegral) {
  const int size = 32;
  const std::vector<float> table = make_split_sum_table(size, 256);
  ASSERT_EQ(table.size(), 2u * size * size);
  // At texel centres the table is the integral; between them within 3e-3 (away from n.v -> 0
  // where B changes fastest).
  EXPECT_LT((lookup_split_sum(table, size, 5.5f / size, 7.5f / size) -
             integrate_split_sum(5.5f / size, 7.5f / size, 256))
                .norm(),
            1e-6);
  for (float n_dot_v : {0.2f, 0.47f, 0.83f})
    for (float roughness : {0.13f, 0.51f, 0.96f})
      EXPECT_LT((lookup_split_sum(table, size, n_dot_v, roughness) -
                 integrate_split_sum(n_dot_v, roughness, 256))
                    .cwiseAbs()
                    .maxCoeff(),
                3e-3)
          << n_dot_v << ", " << roughness;
}

ShRgb random_sh(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  ShRgb sh;
  for (auto& c : sh.c) c = {u(rng), u(rng), u(rng)};
  return sh;
}

// R&H's eq. 12 matrices give eq. 13's irradiance (core's sh_irradiance) at every normal.
TEST(ShUniforms, IrradianceMatricesEqualCoreIrradiance) {
  std::mt19937 rng(3);
  const ShRgb sh = random_sh(rng);
  const auto m = irradiance_matrices(sh);
  std::normal_distribution<double> g;
  for (int k = 0; k < 50; ++k) {
    const Eigen::Vector3d n = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const Eigen::Vector4f h(static_cast<float>(n.x()), static_cast<float>(n.y()),
                            static_cast<float>(n.z()), 1.f);
    const Eigen::Vector3d core = sh_irradiance(sh, n);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(h.dot(m[static_cast<std::size_t>(c)] * h), core[c], 1e-5) << k << "," << c;
  }
  ShRgb two_bands;
  two_bands.bands = 2;
  EXPECT_THROW(irradiance_matrices(two_bands), std::invalid_argument);
}

// The PRT light is the radiance in the object frame: dotted with the basis at an object-frame
// direction it gives the world-frame function at the rotated direction. Channels at 28 c.
TEST(ShUniforms, PrtLightIsTheRadianceInTheObjectFrame) {
  std::mt19937 rng(4);
  const ShRgb sh = random_sh(rng);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.9, Eigen::Vector3d(-0.2, 0.6, 0.7).normalized()).toRotationMatrix();
  const auto light = prt_light(sh, R);
  std::normal_distribution<double> g;
  for (int k = 0; k < 20; ++k) {
    const Eigen::Vector3d d_object = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const ShBasis y = sh_basis(d_object);
    const Eigen::Vector3d world = sh.evaluate(R * d_object);
    for (int c = 0; c < 3; ++c) {
      double v = 0;
      for (int i = 0; i < kShMaxCount; ++i)
        v += light[static_cast<std::size_t>(28 * c + i)] * y[static_cast<std::size_t>(i)];
      EXPECT_NEAR(v, world[c], 1e-5) << k << "," << c;
    }
  }
  for (int c = 0; c < 3; ++c)
    for (int pad = 25; pad < 28; ++pad)
      EXPECT_EQ(light[static_cast<std::size_t>(28 * c + pad)], 0.f);
}

}  // namespace
}  // namespace probeless::render
