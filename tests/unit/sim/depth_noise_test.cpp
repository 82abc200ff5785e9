#include "core/depth_noise.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace probeless {
namespace {

constexpr double kFocal = 525.0;

DepthImage flat_wall(double z_m) {
  return DepthImage(640, 480, static_cast<std::uint16_t>(std::lround(z_m * 1000)));
}

struct ErrorStats {
  double mean_mm = 0, sigma_mm = 0;
  double valid_fraction = 0;
};

// Error of the noisy depth against the clean one over the valid pixels of several seeds,
// away from the image border (where windows do not fit).
ErrorStats wall_error(double z_m, int seeds) {
  const DepthImage clean = flat_wall(z_m);
  double sum = 0, sum_sq = 0;
  std::size_t n = 0, total = 0;
  for (int s = 0; s < seeds; ++s) {
    const DepthImage noisy = apply_kinect_noise(clean, kFocal, 1000 + s);
    for (int y = 10; y < noisy.height() - 10; ++y) {
      for (int x = 10; x < noisy.width() - 10; ++x) {
        ++total;
        if (noisy.at(x, y) == 0) continue;
        const double e = static_cast<double>(noisy.at(x, y)) - clean.at(x, y);
        sum += e;
        sum_sq += e * e;
        ++n;
      }
    }
  }
  ErrorStats st;
  st.mean_mm = sum / n;
  st.sigma_mm = std::sqrt(sum_sq / n - st.mean_mm * st.mean_mm);
  st.valid_fraction = static_cast<double>(n) / total;
  return st;
}

TEST(DepthNoise, AxialSigmaIsNguyensModel) {
  // sigma_z = 0.0012 + 0.0019 (z - 0.4)^2 (Nguyen, Izadi & Lovell 2012).
  EXPECT_NEAR(kinect_axial_sigma_m(1.0), 0.0012 + 0.0019 * 0.36, 1e-12);
  EXPECT_NEAR(kinect_axial_sigma_m(3.0), 0.0012 + 0.0019 * 6.76, 1e-12);
}

class FlatWall : public ::testing::TestWithParam<double> {};

TEST_P(FlatWall, ErrorHasTheModelsMeanAndSigma) {
  const double z = GetParam();
  const ErrorStats st = wall_error(z, 6);
  const double model_mm = 1000 * kinect_axial_sigma_m(z);
  EXPECT_GT(st.valid_fraction, 0.95) << "a flat wall in range is measured almost everywhere";
  EXPECT_NEAR(st.sigma_mm, model_mm, 0.10 * model_mm) << "at z = " << z << " m";
  EXPECT_LT(std::abs(st.mean_mm), 0.10 * model_mm) << "at z = " << z << " m";
}

INSTANTIATE_TEST_SUITE_P(OneAndThreeMetres, FlatWall, ::testing::Values(1.0, 3.0));

// On one plane the millimetre output and the 1/8 px disparity levels make the error a few
// discrete values, so sigma wobbles with where the plane falls between levels (about +-20 %
// below 1.5 m); over planes a little apart it is the model's.
TEST(DepthNoise, VarianceOverNearbyPlanesIsTheModels) {
  for (double z0 : {0.7, 2.0}) {
    double ratio = 0;
    int planes = 0;
    for (int k = -10; k <= 10; ++k, ++planes) {
      const DepthImage clean(160, 120,
                             static_cast<std::uint16_t>(std::lround((z0 + 0.0013 * k) * 1000)));
      double sum = 0, sum_sq = 0;
      int n = 0;
      for (int seed = 0; seed < 3; ++seed) {
        const DepthImage noisy = apply_kinect_noise(clean, kFocal, 50 + seed);
        for (int y = 10; y < 110; ++y)
          for (int x = 10; x < 150; ++x) {
            if (noisy.at(x, y) == 0) continue;
            const double e = static_cast<double>(noisy.at(x, y)) - clean.at(x, y);
            sum += e;
            sum_sq += e * e;
            ++n;
          }
      }
      const double model = 1000 * kinect_axial_sigma_m(clean.at(0, 0) / 1000.0);
      ratio += (sum_sq / n - (sum / n) * (sum / n)) / (model * model);
    }
    EXPECT_NEAR(std::sqrt(ratio / planes), 1.0, 0.05) << "around " << z0 << " m";
  }
}

TEST(DepthNoise, DeterministicInTheSeed) {
  const DepthImage clean = flat_wall(2.0);
  EXPECT_EQ(apply_kinect_noise(clean, kFocal, 7), apply_kinect_noise(clean, kFocal, 7));
  EXPECT_NE(apply_kinect_noise(clean, kFocal, 7), apply_kinect_noise(clean, kFocal, 8));
}

TEST(DepthNoise, NothingOutsideTheRangeOrWhereThereIsNoSurface) {
  for (double z : {0.3, 4.5}) {
    const DepthImage noisy = apply_kinect_noise(flat_wall(z), kFocal, 1);
    for (std::uint16_t v : noisy.elements()) {
      ASSERT_EQ(v, 0) << "z = " << z;
    }
  }
  const DepthImage nothing = apply_kinect_noise(DepthImage(64, 48, 0), kFocal, 1);
  for (std::uint16_t v : nothing.elements()) {
    ASSERT_EQ(v, 0);
  }
}

TEST(DepthNoise, HolesOnDepthEdgesNotOnSurfaces) {
  // A box at 1 m in front of a wall at 2 m: the silhouette loses its depth, the middle of
  // each surface keeps it.
  DepthImage clean = flat_wall(2.0);
  for (int y = 140; y < 340; ++y)
    for (int x = 220; x < 420; ++x) clean.at(x, y) = 1000;
  int edge_holes = 0, edge_pixels = 0, inner_holes = 0, inner_pixels = 0;
  const DepthImage noisy = apply_kinect_noise(clean, kFocal, 3);
  for (int y = 160; y < 320; ++y) {
    for (int x : {219, 220}) {  // the silhouette's columns
      ++edge_pixels;
      edge_holes += noisy.at(x, y) == 0;
    }
    for (int x : {120, 320, 520}) {  // wall, box, wall
      ++inner_pixels;
      inner_holes += noisy.at(x, y) == 0;
    }
  }
  EXPECT_GT(edge_holes, edge_pixels / 2);
  EXPECT_LT(inner_holes, inner_pixels / 50);
}

TEST(DepthNoise, WorksOnAnySize) {
  const DepthImage small(5, 3, 1500);
  EXPECT_EQ(apply_kinect_noise(small, 100, 1).width(), 5);
  EXPECT_TRUE(apply_kinect_noise(DepthImage(), 100, 1).empty());
  EXPECT_THROW(apply_kinect_noise(small, 0, 1), std::invalid_argument);
}

}  // namespace
}  // namespace probeless
