// The two colour outputs (display RGBA8 and linear float, alpha = coverage), the display
// exposure, light updates through new Environment instances, and the errors for objects
// whose material lacks what it needs.
#include <gtest/gtest.h>

#include <cmath>

#include "material_reference.hpp"

namespace probeless::render {
namespace {

using testing::environment_of;
using testing::SphereView;
using S = Material::Shading;
using RenderTargetTest = testing::MaterialFixture;

std::shared_ptr<const Environment> constant(double value) {
  return environment_of(8,
                        [=](const Eigen::Vector3d&) { return Eigen::Vector3d::Constant(value); });
}

// The float target holds the same picture as the display target before encoding: alpha is
// 1 exactly where the display's is 255, and the display is (linear x exposure)^(1/2.2).
TEST_F(RenderTargetTest, FloatTargetIsTheLinearDisplayPicture) {
  const SphereView view;
  VirtualObject pawn;
  pawn.mesh = std::make_shared<const Mesh>(make_pawn(0.2f));
  pawn.T_world_object.translation = {0, 0, -0.1};
  pawn.material.base_colour = {0.75f, 0.18f, 0.12f, 1.f};
  RenderTarget display, linear;
  linear.output = ColourOutput::LinearFloat;
  renderer().render(view.camera(), {pawn}, display);
  renderer().render(view.camera(), {pawn}, linear);
  EXPECT_TRUE(linear.colour.empty()) << "the float output leaves the display image alone";
  ASSERT_EQ(linear.radiance.width(), view.k.width);
  int covered = 0;
  for (int y = 0; y < view.k.height; ++y)
    for (int x = 0; x < view.k.width; ++x) {
      const float a = linear.radiance.at(x, y, 3);
      ASSERT_TRUE(a == 0.f || a == 1.f);
      ASSERT_EQ(a == 1.f, display.colour.at(x, y, 3) == 255) << x << "," << y;
      ASSERT_EQ(linear.depth_mm.at(x, y), display.depth_mm.at(x, y));
      covered += a == 1.f;
      for (int c = 0; c < 3; ++c) {
        const double encoded = 255.0 * std::pow(linear.radiance.at(x, y, c), 1 / 2.2);
        ASSERT_NEAR(display.colour.at(x, y, c), encoded, 1.01) << x << "," << y << "," << c;
      }
    }
  EXPECT_GT(covered, 1000);
}

// HDR radiance passes through the float target unclamped; the display target scales it by
// the exposure before gamma and clamping.
TEST_F(RenderTargetTest, HdrValuesAndExposure) {
  const SphereView view;
  Material mirror;
  mirror.shading = S::Mirror;
  const auto bright = constant(40.0);
  RenderTarget linear;
  linear.output = ColourOutput::LinearFloat;
  renderer().render(view.camera(), {view.object(mirror, bright)}, linear);
  EXPECT_FLOAT_EQ(linear.radiance.at(120, 90, 0), 40.f);
  RenderTarget display;
  display.exposure = 1.f / 160.f;  // 40 -> 0.25
  renderer().render(view.camera(), {view.object(mirror, bright)}, display);
  EXPECT_NEAR(display.colour.at(120, 90, 1), 255.0 * std::pow(0.25, 1 / 2.2), 1.0);
  display.exposure = 1.f;
  renderer().render(view.camera(), {view.object(mirror, bright)}, display);
  EXPECT_EQ(display.colour.at(120, 90, 1), 255);  // clamped
}

// A light update is a new Environment: the picture follows it, and the old one can go.
TEST_F(RenderTargetTest, NewEnvironmentChangesThePicture) {
  const SphereView view;
  Material diffuse;
  diffuse.shading = S::ShDiffuse;
  RenderTarget out;
  out.output = ColourOutput::LinearFloat;
  auto light = constant(1.0);
  renderer().render(view.camera(), {view.object(diffuse, light)}, out);
  EXPECT_NEAR(out.radiance.at(120, 90, 0), 1.0, 1e-3);
  for (double value : {2.0, 3.0, 0.5}) {
    light = constant(value);  // the previous one expires here
    renderer().render(view.camera(), {view.object(diffuse, light)}, out);
    EXPECT_NEAR(out.radiance.at(120, 90, 0), value, 1e-3 * value);
  }
  Material rough;
  rough.shading = S::RoughMetal;
  renderer().render(view.camera(), {view.object(rough, light)}, out);
  EXPECT_NEAR(out.radiance.at(120, 90, 0), 0.5, 2e-3);
}

TEST_F(RenderTargetTest, MissingInputsAreRefused) {
  const SphereView view;
  RenderTarget out;
  for (S shading : {S::Mirror, S::RoughMetal, S::Refraction, S::ShDiffuse, S::PrtDiffuse}) {
    Material m;
    m.shading = shading;
    try {
      renderer().render(view.camera(), {view.object(m, nullptr)}, out);
      ADD_FAILURE() << "no environment accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("environment"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("sphere"), std::string::npos) << e.what();
    }
  }
  Material prt;
  prt.shading = S::PrtDiffuse;
  EXPECT_THROW(renderer().render(view.camera(), {view.object(prt, constant(1))}, out),
               std::invalid_argument);  // no transfer
  Mesh wrong = make_sphere(0.1f, 16, 8);
  wrong.prt_transfer.assign(24 * wrong.vertex_count(), 0.f);
  EXPECT_THROW(wrong.validate(), std::invalid_argument);
  wrong.prt_transfer.assign(25 * wrong.vertex_count(), 0.f);
  wrong.prt_transfer[7] = std::nanf("");
  EXPECT_THROW(wrong.validate(), std::invalid_argument);
  Material glass;
  glass.shading = S::Refraction;
  glass.ior = 0.f;
  EXPECT_THROW(renderer().render(view.camera(), {view.object(glass, constant(1))}, out),
               std::invalid_argument);
  EXPECT_THROW(make_environment(ImageRGBAF(4, 23), ShRgb{}), std::invalid_argument);
  ImageRGBAF faces(4, 24, 1.f);
  faces.at(1, 2, 0) = std::numeric_limits<float>::infinity();
  EXPECT_THROW(make_environment(faces, ShRgb{}), std::invalid_argument);
  ShRgb two_bands;
  two_bands.bands = 2;
  EXPECT_THROW(make_environment(ImageRGBAF(4, 24, 1.f), two_bands), std::invalid_argument);
}

// The environment layout: a keyframe's stacked faces and a core Cubemap describe the same
// directions (face f at rows f n .. f n + n - 1), both ways.
TEST(EnvironmentLayout, StackedFacesAndCubemapAgree) {
  const Cubemap cube = testing::cubemap_of(
      4, [](const Eigen::Vector3d& d) { return Eigen::Vector3d(d.x() + 2, d.y() + 2, d.z() + 2); });
  const Environment e = make_environment(cube);
  EXPECT_EQ(e.face_size(), 4);
  EXPECT_EQ(e.faces.height(), 24);
  EXPECT_FLOAT_EQ(e.faces.at(1, 2 * 4 + 3, 1), cube.face(CubeFace::PosY).at(1, 3, 1));
  EXPECT_TRUE(to_cubemap(e) == cube);
  EXPECT_NEAR(e.sh.c[0].x(), 2 * 2 * std::sqrt(std::numbers::pi), 1e-6);
}

}  // namespace
}  // namespace probeless::render
