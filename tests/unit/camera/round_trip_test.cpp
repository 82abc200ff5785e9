// project(unproject(px)) and unproject(project(ray)) over grids that cover the whole image
// (pinhole) or the whole image circle (fisheyes).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "core/camera/kannala_brandt.hpp"
#include "core/camera/pinhole.hpp"

namespace probeless {
namespace {

constexpr double kPi = std::numbers::pi;

// acos loses half the digits near 0; atan2 of |cross| and dot does not.
double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Every pixel on a grid of step `step` inside the image; returns how many round-tripped.
int expect_pixel_round_trip(const CameraModel& cam, double step, double tol_px) {
  int n = 0;
  for (double y = -0.49; y < cam.height() - 0.5; y += step)
    for (double x = -0.49; x < cam.width() - 0.5; x += step) {
      const Eigen::Vector2d px(x, y);
      const auto ray = cam.unproject(px);
      if (!ray) continue;
      EXPECT_NEAR(ray->norm(), 1.0, 1e-12);
      const auto back = cam.project(*ray);
      EXPECT_TRUE(back) << cam.kind() << " at " << px.transpose();
      if (back) {
        EXPECT_LT((*back - px).norm(), tol_px) << cam.kind() << " at " << px.transpose();
      }
      ++n;
    }
  return n;
}

// Rays on a (theta, phi) grid from the axis out to max_theta.
void expect_ray_round_trip(const CameraModel& cam, double max_theta, double tol_rad) {
  for (double theta = 0; theta <= max_theta; theta += max_theta / 40)
    for (double phi = -kPi; phi < kPi; phi += kPi / 36) {
      const Eigen::Vector3d ray(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                std::cos(theta));
      const auto px = cam.project(ray);
      ASSERT_TRUE(px) << cam.kind() << " theta=" << theta << " phi=" << phi;
      const auto back = cam.unproject(*px);
      ASSERT_TRUE(back) << cam.kind() << " theta=" << theta << " phi=" << phi;
      EXPECT_LT(angle_between(*back, ray), tol_rad)
          << cam.kind() << " theta=" << theta << " phi=" << phi;
    }
}

PinholeCamera distorted_pinhole() {
  // A Kinect-v1-class colour camera with typical calibrated distortion.
  return PinholeCamera({640, 480, 525.0, 523.0, 319.5, 239.5},
                       {0.2624, -0.9531, -0.0054, 0.0026, 1.1633});
}

TEST(Pinhole, IdealProjectsLikeK) {
  const PinholeCamera cam;
  const auto px = cam.project({0.1, -0.2, 2.0});
  ASSERT_TRUE(px);
  EXPECT_NEAR(px->x(), 525.0 * 0.05 + 319.5, 1e-12);
  EXPECT_NEAR(px->y(), 525.0 * -0.1 + 239.5, 1e-12);
  EXPECT_FALSE(cam.project({0, 0, -1}));
  EXPECT_FALSE(cam.project({1, 0, 0}));
  const auto centre = cam.unproject({319.5, 239.5});
  ASSERT_TRUE(centre);
  EXPECT_NEAR((*centre - Eigen::Vector3d(0, 0, 1)).norm(), 0, 1e-15);
  const Eigen::Matrix3d K = cam.matrix();
  EXPECT_EQ(K(0, 0), 525.0);
  EXPECT_EQ(K(1, 2), 239.5);
  EXPECT_EQ(K(2, 2), 1.0);
}

TEST(Pinhole, DistortionMatchesOpenCvFormula) {
  // Hand evaluation of OpenCV's projectPoints formula at one point.
  const PinholeCamera cam({640, 480, 500, 500, 320, 240}, {0.1, 0.01, 0.001, -0.002, 0.001});
  const double x = 0.3, y = -0.2, r2 = x * x + y * y;
  const double radial = 1 + 0.1 * r2 + 0.01 * r2 * r2 + 0.001 * r2 * r2 * r2;
  const double xd = x * radial + 2 * 0.001 * x * y + -0.002 * (r2 + 2 * x * x);
  const double yd = y * radial + 0.001 * (r2 + 2 * y * y) + 2 * -0.002 * x * y;
  const auto px = cam.project({x, y, 1.0});
  ASSERT_TRUE(px);
  EXPECT_NEAR(px->x(), 500 * xd + 320, 1e-10);
  EXPECT_NEAR(px->y(), 500 * yd + 240, 1e-10);
}

TEST(Pinhole, RoundTripsOverTheWholeImage) {
  const PinholeCamera ideal;
  EXPECT_EQ(expect_pixel_round_trip(ideal, 7.3, 1e-9), 88 * 66);
  const PinholeCamera cam = distorted_pinhole();
  // Every pixel of the image must unproject: the distortion is moderate.
  const int n = expect_pixel_round_trip(cam, 7.3, 1e-6);
  EXPECT_EQ(n, 88 * 66);
  // Rays out to the image corners' angle (about 40 deg off axis).
  expect_ray_round_trip(cam, 0.65, 1e-9);
}

TEST(Pinhole, FoldedDistortionDoesNotWrapFarRaysIntoTheImage) {
  // With k1 < 0 alone, r (1 + k1 r^2) peaks at r = 1 / sqrt(-3 k1) and then falls back: a ray
  // beyond that radius must not be projected onto the image.
  const PinholeCamera cam({640, 480, 300, 300, 319.5, 239.5}, {-0.3, 0, 0, 0, 0});
  const double r_max = 1 / std::sqrt(0.9);
  EXPECT_TRUE(cam.project({0.99 * r_max, 0, 1}));
  EXPECT_FALSE(cam.project({1.01 * r_max, 0, 1}));
  EXPECT_FALSE(cam.project({3.0, 0, 1}));
}

TEST(KannalaBrandt, EquidistantGeometry) {
  const auto cam = KannalaBrandtCamera::equidistant(1024, 190);
  EXPECT_EQ(cam.width(), 1024);
  EXPECT_EQ(cam.kind(), "kannala_brandt");
  const auto& p = cam.params();
  EXPECT_DOUBLE_EQ(p.max_theta, 95 * kPi / 180);
  // The optical axis lands on the centre; 90 deg lands at radius 512 * 90 / 95.
  const auto c = cam.project({0, 0, 1});
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->x(), 511.5, 1e-12);
  EXPECT_NEAR(c->y(), 511.5, 1e-12);
  const auto side = cam.project({1, 0, 0});
  ASSERT_TRUE(side);
  EXPECT_NEAR(side->x() - 511.5, 512.0 * 90 / 95, 1e-9);
  // The rim of the field of view is the image circle of diameter 1024.
  const double a = 95 * kPi / 180;
  const auto rim = cam.project({0, std::sin(a), std::cos(a)});
  ASSERT_TRUE(rim);
  EXPECT_NEAR(rim->y() - 511.5, 512.0, 1e-9);
  EXPECT_FALSE(cam.project({0, std::sin(a + 1e-3), std::cos(a + 1e-3)}));
  EXPECT_FALSE(cam.project({0, 0, -1}));
  EXPECT_FALSE(cam.project({0, 0, 0}));
  // Corners of the square image lie outside the image circle: no ray.
  EXPECT_FALSE(cam.unproject({0, 0}));
}

TEST(KannalaBrandt, EquidistantRoundTrips) {
  const auto cam = KannalaBrandtCamera::equidistant(640, 190);
  const int n = expect_pixel_round_trip(cam, 3.1, 1e-9);
  // About pi/4 of the square is the image circle.
  EXPECT_NEAR(n, kPi / 4 * (640 / 3.1) * (640 / 3.1), 0.01 * n);
  expect_ray_round_trip(cam, cam.params().max_theta, 1e-12);
}

TEST(KannalaBrandt, DistortedRoundTrips) {
  // Coefficients of the order cv::fisheye::calibrate returns for a 185-190 deg lens.
  KannalaBrandtParams p;
  p.width = 1280;
  p.height = 960;
  p.fx = 330.2;
  p.fy = 329.7;
  p.cx = 641.3;
  p.cy = 478.9;
  p.k = {0.0312, -0.0147, 0.0052, -0.0011};
  p.max_theta = 1.65;
  const KannalaBrandtCamera cam(p);
  const int n = expect_pixel_round_trip(cam, 5.3, 1e-8);
  EXPECT_GT(n, 10000);
  expect_ray_round_trip(cam, p.max_theta, 1e-12);
  // Matches the formula at one ray.
  const double theta = 0.8, t2 = theta * theta;
  const double td = theta * (1 + p.k[0] * t2 + p.k[1] * t2 * t2 + p.k[2] * t2 * t2 * t2 +
                             p.k[3] * t2 * t2 * t2 * t2);
  const auto px = cam.project({std::sin(theta), 0, std::cos(theta)});
  ASSERT_TRUE(px);
  EXPECT_NEAR(px->x(), p.fx * td + p.cx, 1e-10);
  EXPECT_NEAR(px->y(), p.cy, 1e-10);
}

TEST(KannalaBrandt, CloneKeepsParameters) {
  const auto cam = KannalaBrandtCamera::equidistant(512, 180);
  const auto copy = cam.clone();
  const auto* kb = dynamic_cast<const KannalaBrandtCamera*>(copy.get());
  ASSERT_NE(kb, nullptr);
  EXPECT_EQ(kb->params(), cam.params());
}

}  // namespace
}  // namespace probeless
