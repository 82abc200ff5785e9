// The baked transfer against what it must equal: the analytic clamped cosine where nothing
// is in the way, an independent Monte Carlo reference for a sphere on a plane, and the
// qualitative effects (self-shadowing, mirrors) the thesis relies on (docs/prt.md "Checks").
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <ranges>

#include "app/render/prt/prt.hpp"
#include "prt_test_support.hpp"
#include "sphere_plane_reference.hpp"

namespace probeless::prt {
namespace {

using testing::kOpenT0;
using testing::max_abs_diff;

constexpr int kReferenceSamples = 400'000;

// (a) A convex object cannot shadow itself: every vertex sees its whole hemisphere.
TEST(PrtSphere, ConstantLightGivesAlbedoTimesRadiance) {
  const render::Mesh sphere = render::make_sphere(0.1f);
  const Bake bake = bake_prt(sphere, {});
  ASSERT_EQ(bake.object.vertex_count(), sphere.vertex_count());
  // Constant radiance c has L_0 = 2 sqrt(pi) c (docs/lighting-math.md "Projection").
  const Eigen::Vector3d c(0.3, 1.0, 2.5);
  ShRgb light;
  light.c[0] = 2 * std::sqrt(testing::kPi) * c;
  const double albedo = 0.6;
  double worst = 0;
  for (std::size_t v = 0; v < sphere.vertex_count(); ++v)
    worst = std::max(
        worst, (albedo * bake.object.radiance(v, light) - albedo * c).norm() / (albedo * c).norm());
  // Cosine-weighted sampling integrates the open hemisphere's T_0 exactly; only a spurious
  // self-hit or a lost ray would move it.
  EXPECT_LT(worst, 1e-6);
  EXPECT_TRUE(bake.ground.positions.empty());
}

TEST(PrtSphere, TransferIsTheClampedCosineTurnedToTheNormal) {
  const render::Mesh sphere = render::make_sphere(0.1f);
  const Bake bake = bake_prt(sphere, {});
  double worst = 0, sum_sq = 0;
  for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
    const auto expected = testing::open_transfer(sphere.normals[v].cast<double>());
    const double e = max_abs_diff(bake.object.at(v), expected);
    worst = std::max(worst, e);
    sum_sq += e * e;
  }
  const double rms = std::sqrt(sum_sq / static_cast<double>(sphere.vertex_count()));
  std::printf("sphere vs analytic, %d samples: max %.2e, rms %.2e (T_0 open %.4f)\n",
              BakeOptions{}.samples, worst, rms, kOpenT0);
  // Measured 9e-4 / 7e-4 at 1024 samples (docs/prt.md "Sample count"); a sign or index
  // mix-up in any band is off by 0.1 or more.
  EXPECT_LT(worst, 2.5e-3);
  EXPECT_LT(rms, 1.5e-3);
}

// (b) The plane's transfer beside a sphere standing on it, at vertices from the contact point
// outwards, against the brute-force reference at the same points.
TEST(PrtSphereOnPlane, GroundMatchesMonteCarloReference) {
  const render::Mesh sphere = testing::sphere_on_floor();
  const Bake bake = bake_prt(sphere, {.ground = testing::floor_ground()});
  const int k = Ground{}.subdivisions, centre = k / 2;
  ASSERT_EQ(bake.ground.vertex_count(), static_cast<std::size_t>((k + 1) * (k + 1)));
  const testing::SpherePlaneScene scene;
  for (int step : {0, 1, 2, 3, 5, 10, 20, 32}) {
    const std::size_t v = static_cast<std::size_t>(centre * (k + 1) + centre + step);
    const Eigen::Vector3d p = bake.ground.positions[v].cast<double>();
    const auto ref =
        testing::reference_transfer(scene, p, Eigen::Vector3d::UnitZ(), kReferenceSamples);
    const double err = max_abs_diff(bake.ground_with_object.at(v), ref);
    const double shadow = kOpenT0 - ref[0];
    std::printf("ground at %.3f m (%.2f r): T_0 bake %.5f ref %.5f, shadow %.5f, max err %.2e\n",
                p.head<2>().norm(), p.head<2>().norm() / 0.1, bake.ground_with_object.at(v)[0],
                ref[0], shadow, err);
    EXPECT_LT(err, 6e-3) << "at " << p.transpose();
  }
  // The grid alone is the clamped cosine about the normal, the same row at every vertex.
  const auto open = testing::open_transfer(Eigen::Vector3d::UnitZ());
  EXPECT_LT(max_abs_diff(bake.ground_without_object.at(0), open), 1e-3);
  for (std::size_t v = 1; v < bake.ground.vertex_count(); ++v)
    ASSERT_TRUE(
        std::ranges::equal(bake.ground_without_object.at(v), bake.ground_without_object.at(0)));
  // What differential rendering adds fades with distance: at the grid's corner (9.8 r away)
  // it is below 1 % of the open T_0.
  const Transfer diff = bake.ground_difference();
  EXPECT_LT(std::abs(diff.at(0)[0]), 0.01 * kOpenT0);
  EXPECT_LT(std::abs(diff.at(0)[0]), 0.01 * std::abs(diff.at(centre * (k + 1) + centre + 1)[0]));
  // At the contact point the sphere fills the whole hemisphere.
  EXPECT_NEAR(bake.ground_with_object.at(static_cast<std::size_t>(centre * (k + 1) + centre))[0],
              0.0, 1e-6);
}

// The plane blocks the object's lower half: its transfer is the reference with V = [w.z > 0].
TEST(PrtSphereOnPlane, ObjectMatchesMonteCarloReference) {
  const render::Mesh sphere = testing::sphere_on_floor();
  const Bake bake = bake_prt(sphere, {.ground = testing::floor_ground()});
  const testing::SpherePlaneScene scene;
  double worst = 0;
  // One vertex per ring, pole to pole, on one meridian.
  for (std::size_t v = 0; v < sphere.vertex_count(); v += 49 * 3) {
    // Off the surface a little, as the bake starts its rays: the float vertex lies a rounding
    // error inside or outside the exact sphere, and a ray would hit it at t ~ 0.
    const Eigen::Vector3d n = sphere.normals[v].cast<double>();
    const auto ref = testing::reference_transfer(
        scene, sphere.positions[v].cast<double>() + 1e-5 * n, n, kReferenceSamples);
    worst = std::max(worst, max_abs_diff(bake.object.at(v), ref));
  }
  std::printf("sphere on plane, object vertices: max err %.2e\n", worst);
  EXPECT_LT(worst, 6e-3);
  // The south pole faces the table: nothing reaches it.
  EXPECT_EQ(bake.object.at(0)[0], 0.f);
}

// (c) The pawn's cove and the underside of its collar see less of the sky than their normals
// would: shadowed transfer is below the open hemisphere's there, and never above it.
TEST(PrtPawn, ShowsSelfShadowing) {
  const render::Mesh pawn = render::make_pawn();
  const Bake bake = bake_prt(pawn, {}, {.samples = 256});
  std::size_t shadowed = 0;
  float lowest = 1;
  for (std::size_t v = 0; v < pawn.vertex_count(); ++v) {
    const float t0 = bake.object.at(v)[0];
    EXPECT_LE(t0, kOpenT0 + 1e-6);
    lowest = std::min(lowest, t0);
    if (t0 < 0.8 * kOpenT0) ++shadowed;
  }
  std::printf("pawn: %zu of %zu vertices below 80 %% of open T_0, lowest %.4f\n", shadowed,
              pawn.vertex_count(), lowest);
  EXPECT_GT(shadowed, pawn.vertex_count() / 20);
  // The top of the head sees the whole sky.
  const auto top = std::max_element(pawn.positions.begin(), pawn.positions.end(),
                                    [](auto& a, auto& b) { return a.z() < b.z(); });
  EXPECT_NEAR(bake.object.at(static_cast<std::size_t>(top - pawn.positions.begin()))[0], kOpenT0,
              1e-6);
}

// (d) A mirror sphere sends the plane's shadow rays on into the sky: its shadow is lighter,
// and matches the reference that reflects off the exact sphere.
TEST(PrtMirror, MirrorSphereCastsALighterShadow) {
  const render::Mesh sphere = testing::sphere_on_floor();
  const Scene diffuse{.ground = testing::floor_ground()};
  Scene mirror = diffuse;
  mirror.mirror = true;
  mirror.mirror_reflectance = 0.9f;
  const Bake a = bake_prt(sphere, diffuse), b = bake_prt(sphere, mirror);
  testing::SpherePlaneScene ref_scene;
  ref_scene.mirror = true;
  ref_scene.reflectance = 0.9;
  const int k = Ground{}.subdivisions, centre = k / 2;
  for (int step : {3, 5, 10, 20}) {
    const std::size_t v = static_cast<std::size_t>(centre * (k + 1) + centre + step);
    const float dark = a.ground_with_object.at(v)[0], light = b.ground_with_object.at(v)[0];
    const auto ref = testing::reference_transfer(ref_scene, b.ground.positions[v].cast<double>(),
                                                 Eigen::Vector3d::UnitZ(), kReferenceSamples);
    std::printf("mirror at step %d: T_0 diffuse %.4f mirror %.4f ref %.4f, open %.4f\n", step, dark,
                light, ref[0], kOpenT0);
    EXPECT_GT(light, dark + 5e-3) << "step " << step;
    EXPECT_LT(light, kOpenT0);
    EXPECT_LT(max_abs_diff(b.ground_with_object.at(v), ref), 6e-3) << "step " << step;
  }
  // Over the grid the mirror takes a good part of the shadow away (rays that it sends down
  // into the table stay dark, so not all of it).
  double shadow_diffuse = 0, shadow_mirror = 0;
  for (std::size_t v = 0; v < a.ground.vertex_count(); ++v) {
    shadow_diffuse += kOpenT0 - a.ground_with_object.at(v)[0];
    shadow_mirror += kOpenT0 - b.ground_with_object.at(v)[0];
  }
  std::printf("summed shadow: diffuse %.3f, mirror %.3f\n", shadow_diffuse, shadow_mirror);
  EXPECT_LT(shadow_mirror, 0.75 * shadow_diffuse);
  // Reflectance 0 is a black mirror: the shadow of a diffuse object.
  mirror.mirror_reflectance = 0.f;
  EXPECT_EQ(bake_prt(sphere, mirror).ground_with_object, a.ground_with_object);
}

// Per-triangle reflectance (the service's scene of several objects): every triangle at the
// scene's reflectance is the mirror bake to the bit, every triangle at 0 the diffuse one, and a
// mesh half mirror lies between them.
TEST(PrtMirror, PerTriangleReflectanceMatchesTheWholeObjectBakes) {
  const render::Mesh sphere = testing::sphere_on_floor(24, 12);
  BakeOptions o;
  o.samples = 256;
  const Scene diffuse{.ground = testing::floor_ground()};
  Scene mirror = diffuse;
  mirror.mirror = true;
  mirror.mirror_reflectance = 0.9f;
  const Bake a = bake_prt(sphere, diffuse, o), b = bake_prt(sphere, mirror, o);
  Scene per = diffuse;
  per.triangle_reflectance.assign(sphere.triangle_count(), 0.9f);
  EXPECT_EQ(bake_prt(sphere, per, o).ground_with_object, b.ground_with_object);
  per.triangle_reflectance.assign(sphere.triangle_count(), 0.f);
  EXPECT_EQ(bake_prt(sphere, per, o).ground_with_object, a.ground_with_object);
  for (std::size_t t = 0; t < sphere.triangle_count(); t += 2) per.triangle_reflectance[t] = 0.9f;
  const Bake half = bake_prt(sphere, per, o);
  double sa = 0, sb = 0, sh = 0;
  for (std::size_t v = 0; v < a.ground.vertex_count(); ++v) {
    sa += a.ground_with_object.at(v)[0];
    sb += b.ground_with_object.at(v)[0];
    sh += half.ground_with_object.at(v)[0];
  }
  EXPECT_GT(sh, sa + 1e-3);
  EXPECT_LT(sh, sb - 1e-3);
  // A wrong count or a value outside 0..1 is an error that names it.
  per.triangle_reflectance.pop_back();
  EXPECT_THROW(bake_prt(sphere, per, o), std::invalid_argument);
  per.triangle_reflectance.assign(sphere.triangle_count(), 1.5f);
  EXPECT_THROW(bake_prt(sphere, per, o), std::invalid_argument);
}

TEST(PrtGround, GridLiesOnThePlaneUnderTheObject) {
  render::Mesh pawn = render::make_pawn(0.2f, 16);
  for (auto& p : pawn.positions) p += Eigen::Vector3f(1, 2, 0);
  Ground g{.plane = {.point = Eigen::Vector3f(0, 0, -0.5f), .normal = Eigen::Vector3f(0, 1, 4)},
           .subdivisions = 10};
  const Eigen::Vector3f n = g.plane.normal.normalized();
  const auto [lo, hi] = pawn.bounds();
  const Eigen::Vector3f centre = (lo + hi) / 2;
  const float radius = (hi - lo).norm() / 2;
  for (std::optional<float> side : {std::optional<float>{}, std::optional<float>{0.3f}}) {
    g.side = side;
    const render::Mesh grid = make_ground_grid(pawn, g);
    ASSERT_EQ(grid.vertex_count(), 121u);
    EXPECT_NO_THROW(grid.validate());
    for (std::size_t v = 0; v < grid.vertex_count(); ++v) {
      EXPECT_NEAR(n.dot(grid.positions[v] - g.plane.point), 0.f, 1e-5f);
      EXPECT_TRUE(grid.normals[v].isApprox(n));
    }
    // The middle vertex is where the box's centre drops onto the plane; the corners are the
    // side apart; the triangles turn counter-clockwise seen from above.
    const Eigen::Vector3f mid = grid.positions[60];
    EXPECT_NEAR((mid - centre).cross(n).norm(), 0.f, 1e-5f);
    const float expected = side ? *side : 8 * radius;
    EXPECT_NEAR((grid.positions[10] - grid.positions[0]).norm(), expected, 1e-5f);
    const auto& ix = grid.indices;
    const auto& p = grid.positions;
    EXPECT_GT((p[ix[1]] - p[ix[0]]).cross(p[ix[2]] - p[ix[0]]).dot(n), 0.f);
    // Graded: the steps next to the centre are a third of the uniform step.
    EXPECT_NEAR((grid.positions[61] - mid).norm(), expected / 10 * (1 + 2 * 0.04f) / 3, 1e-5f);
  }
}

TEST(PrtBake, ResultDoesNotDependOnTheThreadCount) {
  const render::Mesh pawn = render::make_pawn(0.2f, 16);
  const Scene scene{.ground = Ground{.subdivisions = 8}};
  const Bake one = bake_prt(pawn, scene, {.samples = 64, .threads = 1});
  const Bake three = bake_prt(pawn, scene, {.samples = 64, .threads = 3});
  EXPECT_EQ(one.object, three.object);
  EXPECT_EQ(one.ground_with_object, three.ground_with_object);
  // And the seed does change it.
  EXPECT_NE(bake_prt(pawn, scene, {.samples = 64, .seed = 2}).object, one.object);
}

}  // namespace
}  // namespace probeless::prt
