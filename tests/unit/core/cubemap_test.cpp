#include <gtest/gtest.h>

#include <numbers>

#include "core/cubemap.hpp"

namespace probeless {
namespace {

TEST(Cubemap, SolidAnglesSumToFourPi) {
  for (int n : {1, 3, 16, 127}) {
    double sum = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) sum += cube_texel_solid_angle(x, y, n);
    EXPECT_NEAR(6 * sum, 4 * std::numbers::pi, 1e-9) << "n=" << n;
  }
}

TEST(Cubemap, DirectionAndTexelRoundTrip) {
  for (int f = 0; f < 6; ++f)
    for (double u : {0.01, 0.3, 0.5, 0.77, 0.99})
      for (double v : {0.02, 0.5, 0.64, 0.98}) {
        const auto d = cube_direction(static_cast<CubeFace>(f), u, v);
        const auto t = cube_texel_from_direction(d);
        EXPECT_EQ(static_cast<int>(t.face), f);
        EXPECT_NEAR(t.u, u, 1e-12);
        EXPECT_NEAR(t.v, v, 1e-12);
      }
}

TEST(Cubemap, AxesLandOnTheirFaces) {
  EXPECT_EQ(cube_texel_from_direction({1, 0, 0}).face, CubeFace::PosX);
  EXPECT_EQ(cube_texel_from_direction({0, -1, 0}).face, CubeFace::NegY);
  EXPECT_EQ(cube_texel_from_direction({0, 0, 2}).face, CubeFace::PosZ);
  EXPECT_EQ(cube_texel_from_direction({0.1, 0.2, -3}).face, CubeFace::NegZ);
}

}  // namespace
}  // namespace probeless
