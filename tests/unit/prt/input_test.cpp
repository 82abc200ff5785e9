// (f) Bad input is refused with std::invalid_argument saying what is wrong.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

#include "app/render/prt/prt.hpp"

namespace probeless::prt {
namespace {

using ::testing::HasSubstr;

std::string error_of(const render::Mesh& m, const Scene& s, const BakeOptions& o = {}) {
  try {
    bake_prt(m, s, o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no std::invalid_argument)";
}

TEST(PrtInput, EmptyOrBrokenMeshes) {
  render::Mesh empty;
  empty.name = "nothing";
  EXPECT_THAT(error_of(empty, {}), HasSubstr("mesh 'nothing' has no triangles"));
  render::Mesh m = render::make_sphere(0.1f, 8, 4);
  m.normals.pop_back();
  EXPECT_THAT(error_of(m, {}), HasSubstr("normals and positions differ"));
  m = render::make_sphere(0.1f, 8, 4);
  m.indices.push_back(100000);
  m.indices.push_back(0);
  m.indices.push_back(1);
  EXPECT_THAT(error_of(m, {}), HasSubstr("index 100000"));
  m = render::make_sphere(0.1f, 8, 4);
  for (auto& p : m.positions) p = Eigen::Vector3f(1, 2, 3);
  EXPECT_THAT(error_of(m, {}), HasSubstr("no extent"));
}

TEST(PrtInput, Samples) {
  const render::Mesh m = render::make_sphere(0.1f, 8, 4);
  BakeOptions o;
  o.samples = 0;
  EXPECT_THAT(error_of(m, {}, o), HasSubstr("samples must be 1..1048576 (got 0)"));
  o.samples = -5;
  EXPECT_THAT(error_of(m, {}, o), HasSubstr("(got -5)"));
  o.samples = 1;  // allowed, if useless
  EXPECT_NO_THROW(bake_prt(m, {}, o));
  o.max_mirror_bounces = -1;
  EXPECT_THAT(error_of(m, {}, o), HasSubstr("max_mirror_bounces"));
}

TEST(PrtInput, Plane) {
  const render::Mesh m = render::make_sphere(0.1f, 8, 4);
  Scene s{.ground = Ground{}};
  s.ground->plane.normal = Eigen::Vector3f::Zero();
  EXPECT_THAT(error_of(m, s), HasSubstr("normal (0, 0, 0) must be finite and non-zero"));
  s.ground->plane.normal = Eigen::Vector3f(0, std::numeric_limits<float>::quiet_NaN(), 1);
  EXPECT_THAT(error_of(m, s), HasSubstr("normal"));
  s.ground->plane.normal = Eigen::Vector3f(0, 0, 5);  // any length is fine
  EXPECT_NO_THROW(bake_prt(m, s, {.samples = 4}));
  s.ground->plane.point.x() = std::numeric_limits<float>::infinity();
  EXPECT_THAT(error_of(m, s), HasSubstr("point must be finite"));
  s.ground = Ground{.subdivisions = 0};
  EXPECT_THAT(error_of(m, s), HasSubstr("subdivisions must be 1..1024 (got 0)"));
  s.ground = Ground{.side_radii = -1};
  EXPECT_THAT(error_of(m, s), HasSubstr("side_radii must be positive"));
  s.ground = Ground{.side = 0.f};
  EXPECT_THAT(error_of(m, s), HasSubstr("side must be positive (got 0)"));
  EXPECT_THROW(make_ground_grid(m, *s.ground), std::invalid_argument);
}

TEST(PrtInput, Reflectance) {
  const render::Mesh m = render::make_sphere(0.1f, 8, 4);
  Scene s{.mirror = true, .mirror_reflectance = 1.5f};
  EXPECT_THAT(error_of(m, s), HasSubstr("mirror_reflectance must be in 0..1 (got 1.5)"));
  s.mirror_reflectance = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THAT(error_of(m, s), HasSubstr("mirror_reflectance"));
}

// A vertex without a normal has no hemisphere: zero transfer, not NaN.
TEST(PrtInput, ZeroNormalGivesZeroTransfer) {
  render::Mesh m = render::make_sphere(0.1f, 8, 4);
  m.normals[5] = Eigen::Vector3f::Zero();
  const Bake b = bake_prt(m, {}, {.samples = 16});
  for (float c : b.object.at(5)) EXPECT_EQ(c, 0.f);
  EXPECT_GT(b.object.at(6)[0], 0.f);
}

}  // namespace
}  // namespace probeless::prt
