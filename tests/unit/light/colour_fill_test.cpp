// The colour camera's view below the fisheye's horizon (kernels/light/colour_fill.hpp).
#include "kernels/light/colour_fill.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace probeless::light {
namespace {

// A camera 1 m above a grey floor (z = 0) looking straight down; every pixel at 1000 mm.
struct FloorView {
  PinholeIntrinsics k;
  RgbdFrame frame;
  Pose T_world_camera;
  explicit FloorView(std::uint8_t grey) {
    frame.colour = ImageRGB8(k.width, k.height);
    frame.depth = DepthImage(k.width, k.height);
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x) {
        for (int c = 0; c < 3; ++c) frame.colour.at(x, y, c) = grey;
        frame.depth.at(x, y, 0) = 1000;
      }
    Eigen::Matrix3d r;  // camera x = world x, camera y = world -y, camera z = world -z
    r << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    T_world_camera.rotation = Eigen::Quaterniond(r);
    T_world_camera.translation = Eigen::Vector3d(0, 0, 1);
  }
};

float* texel_towards(envmap::ImageRGBAF& t, const Eigen::Vector3f& d) {
  const int n = envmap::face_size_of(t);
  const envmap::CubeCoord c = envmap::cube_coord_of(d);
  const int x = std::min(static_cast<int>(c.u * n), n - 1);
  const int y = std::min(static_cast<int>(c.v * n), n - 1);
  return &t.at(x, c.face * n + y, 0);
}

TEST(ColourFill, UnobservedTexelsBelowTakeTheFloorsRadiance) {
  FloorView view(128);
  envmap::ImageRGBAF texels = envmap::make_texels(32);  // all 0: nothing observed
  // One texel just above the horizon was observed by the fisheye: it keeps its value (the
  // floor seen from 1 m up reaches no direction above it anyway). One below was too, but
  // below the horizon the colour camera's value wins.
  float* observed = texel_towards(texels, {1, 0.2f, 0.05f});
  float* below = texel_towards(texels, {0.1f, 0.1f, -1});
  below[3] = 1;
  observed[0] = observed[1] = observed[2] = 7;
  observed[3] = 1;
  const Eigen::Vector3d e(2, 3, 4);
  const ColourFillStats s = fill_from_colour(texels, Eigen::Vector3d(0, 0, 0.1), view.frame, view.k,
                                             view.T_world_camera, e);
  EXPECT_EQ(s.samples, 320 * 240);
  EXPECT_GT(s.filled_texels, 32 * 32 / 2);
  const double linear = std::pow(128 / 255.0, 2.2);
  const float* down = texel_towards(texels, {0, 0, -1});
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(down[c], linear * e[c], 1e-4) << c;
  EXPECT_FLOAT_EQ(down[3], 0.5f) << "a filled texel is marked as such";
  EXPECT_NEAR(below[0], linear * e[0], 1e-4);
  EXPECT_FLOAT_EQ(below[3], 0.5f);
  EXPECT_EQ(observed[0], 7) << "the fisheye's texel stays";
  EXPECT_EQ(observed[3], 1);
  // Nothing the camera saw lies above the point: the upper texels stay as they were.
  const float* up = texel_towards(texels, {0.1f, 0.2f, 1});
  EXPECT_EQ(up[0], 0);
  EXPECT_EQ(up[3], 0);
}

// The service keeps one ColourFill and its buffers between snapshots: a fill after others (a
// brighter floor, another face size) gives exactly what a fresh fill gives, nothing of the
// earlier calls' sums left behind.
TEST(ColourFill, AKeptFillerForgetsThePreviousSnapshot) {
  const FloorView dark(60), bright(200);
  const Eigen::Vector3d e(2, 3, 4), where(0, 0, 0.1);
  ColourFill kept;
  envmap::ImageRGBAF warmup = envmap::make_texels(64);
  kept.fill(warmup, where, bright.frame, bright.k, bright.T_world_camera, e);
  envmap::ImageRGBAF again = envmap::make_texels(32), fresh = envmap::make_texels(32);
  kept.fill(again, where, bright.frame, bright.k, bright.T_world_camera, e);
  again = envmap::make_texels(32);
  const ColourFillStats a = kept.fill(again, where, dark.frame, dark.k, dark.T_world_camera, e);
  const ColourFillStats b =
      fill_from_colour(fresh, where, dark.frame, dark.k, dark.T_world_camera, e);
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_EQ(a.filled_texels, b.filled_texels);
  EXPECT_GT(a.filled_texels, 0);
  for (int y = 0; y < fresh.height(); ++y)
    for (int x = 0; x < fresh.width(); ++x)
      for (int c = 0; c < 4; ++c) ASSERT_EQ(again.at(x, y, c), fresh.at(x, y, c)) << x << " " << y;
  EXPECT_THROW(ColourFill(ColourFillParams{.stride = 0}), std::invalid_argument);
}

// Clipped colour only bounds the radiance from below: where it is, the fisheye's value stays
// (below the horizon too) and nothing is filled. A pixel without depth has no point.
TEST(ColourFill, SaturatedAndDepthlessPixelsAreSkipped) {
  FloorView view(255);
  envmap::ImageRGBAF texels = envmap::make_texels(16);
  float* below = texel_towards(texels, {0.1f, 0.1f, -1});
  below[0] = below[1] = below[2] = 5000;
  below[3] = 1;
  const ColourFillStats s = fill_from_colour(texels, Eigen::Vector3d(0, 0, 0.1), view.frame, view.k,
                                             view.T_world_camera, Eigen::Vector3d::Ones());
  EXPECT_EQ(s.samples, 0);
  EXPECT_EQ(s.clipped, 320 * 240);
  EXPECT_EQ(s.filled_texels, 0);
  EXPECT_EQ(below[0], 5000) << "a clipped view does not replace the fisheye's bright texel";
  EXPECT_EQ(below[3], 1);
  FloorView dark(10);
  for (int y = 0; y < dark.k.height; ++y)
    for (int x = 0; x < dark.k.width; ++x) dark.frame.depth.at(x, y, 0) = 0;
  EXPECT_EQ(fill_from_colour(texels, Eigen::Vector3d(0, 0, 0.1), dark.frame, dark.k,
                             dark.T_world_camera, Eigen::Vector3d::Ones())
                .filled_texels,
            0);
}

// Above the horizon only a texel's own samples fill it: the floor seen from below covers the
// zenith, and the coarse blocks that fill the gaps below the horizon would otherwise paint
// the whole upper face with it (on the sim: a bright window painted as wall).
TEST(ColourFill, AboveTheHorizonOnlyNearSamplesFill) {
  FloorView view(128);
  const Eigen::Vector3d under_the_floor(0, 0, -0.5);
  const Eigen::Vector3f oblique(1, 0, 0.3f);  // 73 deg from the zenith: no floor sample there
  envmap::ImageRGBAF texels = envmap::make_texels(32);
  fill_from_colour(texels, under_the_floor, view.frame, view.k, view.T_world_camera,
                   Eigen::Vector3d::Ones());
  EXPECT_GT(texel_towards(texels, {0, 0, 1})[3], 0) << "the zenith has samples";
  EXPECT_EQ(texel_towards(texels, oblique)[3], 0);
  ColourFillParams coarse;
  coarse.levels_above_horizon = coarse.max_level + 1;
  envmap::ImageRGBAF filled = envmap::make_texels(32);
  fill_from_colour(filled, under_the_floor, view.frame, view.k, view.T_world_camera,
                   Eigen::Vector3d::Ones(), coarse);
  EXPECT_GT(texel_towards(filled, oblique)[3], 0) << "the control: coarse blocks reach it";
}

TEST(ColourFill, RejectsAFrameOfAnotherSize) {
  FloorView view(100);
  PinholeIntrinsics other = view.k;
  other.width = 320;
  envmap::ImageRGBAF texels = envmap::make_texels(8);
  EXPECT_THROW(fill_from_colour(texels, Eigen::Vector3d::Zero(), view.frame, other,
                                view.T_world_camera, Eigen::Vector3d::Ones()),
               std::invalid_argument);
  ColourFillParams bad;
  bad.stride = 0;
  EXPECT_THROW(fill_from_colour(texels, Eigen::Vector3d::Zero(), view.frame, view.k,
                                view.T_world_camera, Eigen::Vector3d::Ones(), bad),
               std::invalid_argument);
}

}  // namespace
}  // namespace probeless::light
