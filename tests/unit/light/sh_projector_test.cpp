#include "kernels/light/sh_projector.hpp"

#include <gtest/gtest.h>

#include <random>

#include "kernels/envmap/keyframe_reprojection.hpp"

namespace probeless::light {
namespace {

TEST(ShProjector, MatchesCoreProjectSh) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> v(0, 100);
  for (int m : {1, 5, 32}) {
    envmap::ImageRGBAF faces = envmap::make_texels(m);
    for (float& x : faces.elements()) x = v(rng);
    const ShRgb want = project_sh(envmap::to_cubemap(faces));
    const ShRgb got = ShProjector(m).project(faces);
    for (int k = 0; k < kShMaxCount; ++k)
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(got.c[k][c], want.c[k][c], 1e-4 * (1 + std::abs(want.c[0][c])))
            << m << " " << k;
      }
  }
}

TEST(ShProjector, ConstantRadianceGivesOnlyL00) {
  const int m = 16;
  envmap::ImageRGBAF faces = envmap::make_texels(m);
  for (int y = 0; y < 6 * m; ++y)
    for (int x = 0; x < m; ++x)
      for (int c = 0; c < 3; ++c) faces.at(x, y, c) = 2.0F;
  const ShRgb sh = ShProjector(m).project(faces);
  // L00 = 2 * 4 pi * Y00, Y00 = 1 / (2 sqrt(pi)).
  EXPECT_NEAR(sh.c[0][0], 2.0 * 4.0 * M_PI * 0.282095, 1e-4);
  for (int k = 1; k < 16; ++k) EXPECT_NEAR(sh.c[k][1], 0.0, 1e-5) << k;
  // Band 4 holds the cubic harmonic x^4 + y^4 + z^4, which texel-centre sampling of a cube
  // aliases slightly (core's project_sh alike): 0.2 % of L00 at 16 px faces.
  for (int k = 16; k < kShMaxCount; ++k) EXPECT_NEAR(sh.c[k][1], 0.0, 3e-3 * sh.c[0][1]) << k;
}

// The table folded through the reprojection gives the SH of the reprojected keyframe (what
// the service reports for the object) from the keyframe's own faces.
TEST(ShProjector, ReprojectedTableEqualsTheSHOfTheReprojection) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> v(1, 100);
  const int m = 8;
  envmap::ImageRGBAF faces = envmap::make_texels(m);
  for (float& x : faces.elements()) x = v(rng);
  const envmap::RoomBox room{{-2.5, -2.5, 0.0}, {2.5, 2.5, 2.7}};
  const Eigen::Vector3d k(0.0, -1.1, 1.15), object(0.0, 0.6, 0.85);
  const envmap::ParallaxConstants p = envmap::reprojection_constants(room, k, object);
  ASSERT_TRUE(p.enabled);
  const ShRgb got = ShProjector(m, p, 4).project(faces);
  const ShRgb want = project_sh(envmap::to_cubemap(
      envmap::reproject_keyframe(faces, k, room, object, m, 4, envmap::Resampling::Bilinear)));
  const ShRgb plain = ShProjector(m).project(faces);
  double diff = 0, moved = 0;
  for (int i = 0; i < kShMaxCount; ++i)
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(got.c[i][c], want.c[i][c], 1e-4 * want.c[0][c]) << i;
      diff += std::abs(got.c[i][c] - want.c[i][c]);
      moved += std::abs(plain.c[i][c] - want.c[i][c]);
    }
  EXPECT_GT(moved, 100 * diff);  // the reprojection changed the SH
  // Without parallax, one sample at each texel centre: the plain table.
  const ShRgb same = ShProjector(m, envmap::ParallaxConstants{}, 1).project(faces);
  for (int i = 0; i < kShMaxCount; ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(same.c[i][c], plain.c[i][c], 1e-4 * plain.c[0][c]);
}

TEST(ShProjector, RejectsAnotherSize) {
  EXPECT_THROW(ShProjector(8).project(envmap::make_texels(4)), std::invalid_argument);
  EXPECT_THROW(ShProjector(0), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::light
