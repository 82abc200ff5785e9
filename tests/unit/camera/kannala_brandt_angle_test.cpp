// The Kannala-Brandt polynomial that core/camera exports for the light stage's image circle
// (kernels/light/light_estimator.cpp): the angle project() scales by.
#include <gtest/gtest.h>

#include <cmath>

#include "core/camera/kannala_brandt.hpp"

namespace probeless {
namespace {

TEST(KannalaBrandtAngle, IsThetaWithoutDistortion) {
  EXPECT_EQ(kannala_brandt_distorted_angle({0, 0, 0, 0}, 0.7), 0.7);
  EXPECT_EQ(kannala_brandt_distorted_angle({0.1, -0.02, 0.003, -0.0004}, 0.0), 0.0);
}

TEST(KannalaBrandtAngle, IsThePolynomial) {
  const std::array<double, 4> k{0.1, -0.02, 0.003, -0.0004};
  const double t = 1.2;
  const double expected = t + k[0] * std::pow(t, 3) + k[1] * std::pow(t, 5) +
                          k[2] * std::pow(t, 7) + k[3] * std::pow(t, 9);
  EXPECT_NEAR(kannala_brandt_distorted_angle(k, t), expected, 1e-14);
}

// A point at angle theta from the axis lands theta_d focal lengths from the centre.
TEST(KannalaBrandtAngle, IsWhereProjectLandsARay) {
  KannalaBrandtParams p;
  p.fx = p.fy = 300;
  p.cx = p.cy = 511.5;
  p.k = {0.05, -0.01, 0.002, -0.0003};
  const KannalaBrandtCamera cam(p);
  const double theta = 1.1;
  const auto px = cam.project(Eigen::Vector3d(std::sin(theta), 0, std::cos(theta)));
  ASSERT_TRUE(px);
  EXPECT_NEAR((px->x() - p.cx) / p.fx, kannala_brandt_distorted_angle(p.k, theta), 1e-12);
}

}  // namespace
}  // namespace probeless
