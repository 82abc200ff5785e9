// core/sphere_sampling: the directions the bake integrates with.
#include "core/sphere_sampling.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <set>

#include "core/sh.hpp"

namespace probeless {
namespace {

TEST(SphereSampling, HammersleyIsStratifiedAndShifted) {
  constexpr std::uint32_t n = 256;
  std::set<int> columns, rows;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Eigen::Vector2d p = hammersley(i, n);
    columns.insert(static_cast<int>(p.x() * n));
    rows.insert(static_cast<int>(p.y() * n));
  }
  // One point in every column and every row of the n x n grid (a (0, 2)-net in base 2).
  EXPECT_EQ(columns.size(), n);
  EXPECT_EQ(rows.size(), n);
  EXPECT_DOUBLE_EQ(hammersley(1, 4).y(), 0.5);
  EXPECT_DOUBLE_EQ(hammersley(3, 4).y(), 0.75);
  const Eigen::Vector2d shifted = hammersley(3, 4, {0.5, 0.5});
  EXPECT_DOUBLE_EQ(shifted.x(), 0.375);  // 0.875 + 0.5 wrapped
  EXPECT_DOUBLE_EQ(shifted.y(), 0.25);
  EXPECT_THROW(hammersley(4, 4), std::invalid_argument);
  EXPECT_EQ(seeded_offset(1), seeded_offset(1));
  EXPECT_NE(seeded_offset(1), seeded_offset(2));
}

// With density cos/pi, the sample mean of f estimates 1/pi * integral f cos over the
// hemisphere: for f = 1 it is 1, for f = cos it is 2/3, for the SH basis the clamped cosine's
// coefficients A_l / pi * y_l0(+z).
TEST(SphereSampling, CosineHemisphereHasDensityCosOverPi) {
  const auto d = cosine_hemisphere_set(4096, 5);
  ASSERT_EQ(d.size(), 4096u);
  double mean_z = 0;
  ShBasis mean_y{};
  for (const auto& w : d) {
    EXPECT_NEAR(w.norm(), 1.0, 1e-12);
    EXPECT_GE(w.z(), 0.0);
    mean_z += w.z() / 4096;
    const ShBasis y = sh_basis(w);
    for (int i = 0; i < kShMaxCount; ++i) mean_y[i] += y[i] / 4096;
  }
  EXPECT_NEAR(mean_z, 2.0 / 3.0, 1e-4);
  EXPECT_NEAR(mean_y[sh_index(0, 0)], 0.28209479177387814, 1e-12);
  EXPECT_NEAR(mean_y[sh_index(1, 0)], 2.0 / 3.0 * 0.4886025119029199, 1e-4);
  EXPECT_NEAR(mean_y[sh_index(2, 0)], 0.25 * 0.6307831305050401, 1e-3);
  for (int m : {-2, -1, 1, 2}) EXPECT_NEAR(mean_y[sh_index(2, m)], 0.0, 1e-3);
  EXPECT_NEAR(cosine_hemisphere({0.5, 0.5}).z(), 1.0, 1e-15);  // the disk's centre: the pole
}

TEST(SphereSampling, OrthonormalBasisAroundAnyNormal) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  std::vector<Eigen::Vector3d> normals{Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ(),
                                       Eigen::Vector3d::UnitX(),
                                       Eigen::Vector3d(1e-9, 0, -1).normalized()};
  for (int k = 0; k < 200; ++k)
    normals.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
  for (const auto& n : normals) {
    const Eigen::Matrix3d m = orthonormal_basis(n);
    EXPECT_TRUE((m.transpose() * m).isIdentity(1e-12)) << n.transpose();
    EXPECT_NEAR(m.determinant(), 1.0, 1e-12) << n.transpose();
    EXPECT_TRUE(m.col(2).isApprox(n)) << n.transpose();
  }
}

}  // namespace
}  // namespace probeless
