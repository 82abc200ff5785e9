// The differential-rendering receiver (Material::Shading::GroundShadow, docs/rendering.md "In
// the service"): a quad on the ground whose transfer is a hand-made difference writes
// albedo * sum dT L with coverage 0 into the float target, its depth pulled towards the camera,
// and is not drawn into the display target.
#include <gtest/gtest.h>

#include <cmath>

#include "material_reference.hpp"

namespace probeless::render {
namespace {

using S = Material::Shading;
using MaterialTest = testing::MaterialFixture;

// A 0.4 m square on z = 0 under the sphere view's centre; every vertex carries dT = (t0, 0...):
// only the constant band, so the delta is uniform: albedo * t0 * L_0.
VirtualObject ground_quad(float t0, std::shared_ptr<const Environment> env, float offset_mm) {
  auto mesh = std::make_shared<Mesh>();
  mesh->name = "quad";
  mesh->positions = {
      {-0.2f, -0.2f, -0.05f}, {0.2f, -0.2f, -0.05f}, {0.2f, 0.2f, -0.05f}, {-0.2f, 0.2f, -0.05f}};
  mesh->normals.assign(4, Eigen::Vector3f::UnitZ());
  mesh->indices = {0, 1, 2, 0, 2, 3};
  mesh->prt_transfer.assign(4 * 25, 0.f);
  for (int v = 0; v < 4; ++v) mesh->prt_transfer[static_cast<std::size_t>(v) * 25] = t0;
  VirtualObject o;
  o.mesh = std::move(mesh);
  o.material.shading = S::GroundShadow;
  o.material.base_colour = {0.5f, 0.5f, 0.5f, 1.f};
  o.material.double_sided = true;
  o.material.depth_offset_mm = offset_mm;
  o.environment = std::move(env);
  return o;
}

TEST_F(MaterialTest, GroundShadowWritesASignedDeltaWithoutCoverage) {
  testing::SphereView view;
  view.eye = {-0.45, 0.0, 0.3};  // looking down at the quad
  const Eigen::Vector3d sky(1.0, 2.0, 4.0);
  auto env = testing::environment_of(16, [&](const Eigen::Vector3d&) { return sky; });
  const float t0 = -0.1f;  // a shadow: the object takes away light
  RenderTarget out;
  out.output = ColourOutput::LinearFloat;
  renderer().render(view.camera(), {ground_quad(t0, env, 50.f)}, out);
  RenderTarget no_offset;
  no_offset.output = ColourOutput::LinearFloat;
  renderer().render(view.camera(), {ground_quad(t0, env, 0.f)}, no_offset);

  // L_0 of a constant c is 2 sqrt(pi) c (core/sh.hpp), so the delta is 0.5 * t0 * 2 sqrt(pi) c.
  const int cx = view.k.width / 2, cy = view.k.height / 2;
  const double l0 = 2.0 * std::sqrt(std::numbers::pi);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(out.radiance.at(cx, cy, c), 0.5 * t0 * l0 * sky[c], 2e-3 * sky[c]) << c;
  EXPECT_EQ(out.radiance.at(cx, cy, 3), 0.0f);  // coverage 0: the compositor's "sum"
  ASSERT_GT(no_offset.depth_mm.at(cx, cy), 0.0f);
  EXPECT_NEAR(out.depth_mm.at(cx, cy), no_offset.depth_mm.at(cx, cy) - 50.f, 0.5f);

  RenderTarget display;  // cannot "add": not drawn at all
  renderer().render(view.camera(), {ground_quad(t0, env, 50.f)}, display);
  EXPECT_EQ(display.colour.at(cx, cy, 3), 0);
  EXPECT_EQ(display.depth_mm.at(cx, cy), 0.0f);
}

TEST_F(MaterialTest, GroundShadowWithoutTransferIsRefused) {
  const testing::SphereView view;
  auto env =
      testing::environment_of(8, [](const Eigen::Vector3d&) { return Eigen::Vector3d(1, 1, 1); });
  VirtualObject o = ground_quad(-0.1f, env, 0.f);
  auto bare = std::make_shared<Mesh>(*o.mesh);
  bare->prt_transfer.clear();
  o.mesh = bare;
  RenderTarget out;
  out.output = ColourOutput::LinearFloat;
  EXPECT_THROW(renderer().render(view.camera(), {o}, out), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::render
