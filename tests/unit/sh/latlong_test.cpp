// Lat-long <-> direction mapping and cubemap <-> lat-long resampling.
#include "core/latlong.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/sh.hpp"
#include "drivers/io/hdr_image.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

constexpr double kPi = std::numbers::pi;

// A smooth environment: a sky gradient, a soft sun and a coloured horizon band.
Eigen::Vector3d smooth_env(const Eigen::Vector3d& d) {
  const Eigen::Vector3d sun = Eigen::Vector3d(0.4, -0.3, 0.8).normalized();
  const double glow = std::exp(8.0 * (d.dot(sun) - 1.0));
  return {1.0 + 0.5 * d.z() + 4.0 * glow, 0.8 + 0.3 * d.x() * d.y() + 3.0 * glow,
          0.6 + 0.4 * std::exp(-10 * d.z() * d.z()) + 2.0 * glow};
}

ImageRGBF smooth_latlong(int w, int h) {
  ImageRGBF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d v = smooth_env(latlong_pixel_direction(x, y, w, h));
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<float>(v[c]);
    }
  return img;
}

TEST(LatLong, AxesOfTheConvention) {
  auto near = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return (a - b).norm() < 1e-12;
  };
  EXPECT_TRUE(near(latlong_direction(0.5, 0.5), {0, -1, 0}));  // image centre
  EXPECT_TRUE(near(latlong_direction(0.75, 0.5), {1, 0, 0}));  // three quarters across
  EXPECT_TRUE(near(latlong_direction(0.25, 0.5), {-1, 0, 0}));
  EXPECT_TRUE(near(latlong_direction(0.0, 0.5), {0, 1, 0}));  // the seam
  EXPECT_TRUE(near(latlong_direction(0.3, 0.0), {0, 0, 1}));  // top row: zenith
  EXPECT_TRUE(near(latlong_direction(0.3, 1.0), {0, 0, -1}));
  EXPECT_NEAR(latlong_uv({0, 1, 0}).x(), 0.0, 1e-15);  // the seam maps to u = 0, not 1
}

TEST(LatLong, DirectionAndUvRoundTrip) {
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 128; ++x) {
      const Eigen::Vector3d d = latlong_pixel_direction(x, y, 128, 64);
      EXPECT_NEAR(d.norm(), 1.0, 1e-12);
      const Eigen::Vector2d uv = latlong_uv(3.0 * d);
      EXPECT_NEAR(uv.x(), (x + 0.5) / 128, 1e-12);
      EXPECT_NEAR(uv.y(), (y + 0.5) / 64, 1e-12);
    }
}

TEST(LatLong, RowSolidAnglesSumToFourPi) {
  for (auto [w, h] : {std::pair{256, 128}, std::pair{7, 3}}) {
    double sum = 0;
    for (int y = 0; y < h; ++y) sum += w * latlong_pixel_solid_angle(y, w, h);
    EXPECT_NEAR(sum, 4 * kPi, 1e-12);
  }
  EXPECT_NEAR(latlong_pixel_solid_angle(0, 4, 2), latlong_pixel_solid_angle(1, 4, 2), 1e-15);
}

TEST(LatLong, BilinearSamplingWrapsAcrossTheSeam) {
  ImageRGBF img(4, 2, 0.0f);
  for (int y = 0; y < 2; ++y) {
    img.at(0, y, 0) = 1;  // first column red
    img.at(3, y, 1) = 1;  // last column green
  }
  // On the seam (u = 0), halfway between the last and the first column centres.
  const Eigen::Vector3f s = sample_latlong(img, latlong_direction(0.0, 0.5));
  EXPECT_NEAR(s[0], 0.5f, 1e-6);
  EXPECT_NEAR(s[1], 0.5f, 1e-6);
}

TEST(LatLong, CubemapFromLatLongSamplesTheFunction) {
  const ImageRGBF env = smooth_latlong(512, 256);
  const Cubemap cube = cubemap_from_latlong(env, 32);
  double worst = 0;
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        const Eigen::Vector3d truth =
            smooth_env(cube_direction(static_cast<CubeFace>(f), (x + 0.5) / 32, (y + 0.5) / 32));
        for (int c = 0; c < 3; ++c)
          worst = std::max(
              worst, std::abs(cube.faces[static_cast<std::size_t>(f)].at(x, y, c) - truth[c]));
      }
  EXPECT_LT(worst, 0.05);  // of values up to about 5; the sun is the sharpest feature
}

TEST(LatLong, CubemapRoundTrip) {
  const ImageRGBF env = smooth_latlong(256, 128);
  const ImageRGBF back = latlong_from_cubemap(cubemap_from_latlong(env, 64), 256, 128);
  double err = 0, norm = 0, worst = 0;
  for (std::size_t i = 0; i < env.elements().size(); ++i) {
    const double d = back.elements()[i] - env.elements()[i];
    err += d * d;
    norm += env.elements()[i] * env.elements()[i];
    worst = std::max(worst, std::abs(d));
  }
  EXPECT_LT(std::sqrt(err / norm), 3e-3);
  EXPECT_LT(worst, 0.1);
  // The light in it survives: SH of the cubemap and of the lat-long map agree.
  const ShRgb a = project_sh_latlong(env), b = project_sh(cubemap_from_latlong(env, 64));
  for (int i = 0; i < kShMaxCount; ++i)
    EXPECT_LT((a.c[static_cast<std::size_t>(i)] - b.c[static_cast<std::size_t>(i)]).norm(), 2e-3)
        << i;
}

TEST(LatLong, ProbeSurvivesTheCubemap) {
  PROBELESS_REQUIRE_DATA("hdr/probes/uffizi.hdr");
  const ImageRGBF probe = read_hdr_image(testing::shared_data_dir() / "hdr/probes/uffizi.hdr");
  const ShRgb a = project_sh_latlong(probe, 3);
  const ShRgb b = project_sh(cubemap_from_latlong(probe, 64), 3);
  for (int i = 0; i < 9; ++i)
    EXPECT_LT((a.c[static_cast<std::size_t>(i)] - b.c[static_cast<std::size_t>(i)]).norm(),
              0.01 * a.c[0].norm())
        << i;
}

TEST(LatLong, RejectsBadSizes) {
  EXPECT_THROW(cubemap_from_latlong(ImageRGBF(), 8), std::invalid_argument);
  EXPECT_THROW(cubemap_from_latlong(ImageRGBF(4, 2), 8, 0), std::invalid_argument);
  EXPECT_THROW(latlong_from_cubemap(Cubemap(), 8, 4), std::invalid_argument);
  EXPECT_THROW(latlong_from_cubemap(Cubemap(4), 0, 4), std::invalid_argument);
}

}  // namespace
}  // namespace probeless
