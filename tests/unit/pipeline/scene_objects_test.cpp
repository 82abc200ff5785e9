// The demo scene from config (docs/rendering.md "In the service"): materials mapped, PRT
// transfer baked, the ground receiver added last with the difference the objects make.
#include "app/pipeline/scene_objects.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

namespace probeless {
namespace {

using S = render::Material::Shading;

TEST(SceneObjects, DefaultSceneIsAMirrorSphereAPrtPawnAndTheGroundReceiver) {
  const ServiceConfig config;  // the built-in demo
  const auto objects = make_scene_objects(config.objects, config.ground);
  ASSERT_EQ(objects.size(), 3u);
  EXPECT_EQ(objects[0].material.shading, S::Mirror);
  EXPECT_TRUE(objects[0].mesh->prt_transfer.empty());
  EXPECT_EQ(objects[1].material.shading, S::PrtDiffuse);
  EXPECT_EQ(objects[1].mesh->prt_transfer.size(), objects[1].mesh->vertex_count() * 25);
  const auto& ground = objects[2];
  EXPECT_EQ(ground.material.shading, S::GroundShadow);
  EXPECT_GT(ground.material.depth_offset_mm, 0.f);
  ASSERT_EQ(ground.mesh->prt_transfer.size(), ground.mesh->vertex_count() * 25);
  // The objects take light away from the ground around them: some vertex's constant band is
  // clearly negative, and none gains light (no interreflection is baked).
  float most_negative = 0.f, most_positive = 0.f;
  for (std::size_t v = 0; v < ground.mesh->vertex_count(); ++v) {
    most_negative = std::min(most_negative, ground.mesh->prt_transfer[v * 25]);
    most_positive = std::max(most_positive, ground.mesh->prt_transfer[v * 25]);
  }
  EXPECT_LT(most_negative, -0.05f);  // unoccluded T_0 is 0.282
  EXPECT_LT(most_positive, 1e-6f);
  // The grid lies on the table under the objects (their lowest base).
  for (const auto& p : ground.mesh->positions) EXPECT_NEAR(p.z(), 0.75f, 1e-4f);

  const auto placeholders = placeholder_objects(objects);
  ASSERT_EQ(placeholders.size(), 2u);
  for (const auto& o : placeholders) EXPECT_EQ(o.material.shading, S::Lambert);
}

// Issue #21 item 5: the chrome sphere reflects the ground's shadow rays on into the room, so
// its shadow is lighter than the same sphere's as a diffuse object; the pawn beside it still
// blocks (its shadow is not lightened with the sphere's).
TEST(SceneObjects, TheMirrorSphereCastsAMirrorsShadow) {
  ServiceConfig config;
  auto ground_shadow = [&](const std::vector<ObjectConfig>& objects) {
    const auto scene = make_scene_objects(objects, config.ground, {});
    const auto& t = scene.back().mesh->prt_transfer;
    std::vector<float> shadow;
    for (std::size_t v = 0; v < t.size() / 25; ++v) shadow.push_back(-t[v * 25]);
    return shadow;
  };
  const auto mirror = ground_shadow(config.objects);
  auto diffuse_objects = config.objects;
  ASSERT_EQ(diffuse_objects[0].material, "mirror");
  diffuse_objects[0].material = "lambert";
  const auto diffuse = ground_shadow(diffuse_objects);
  ASSERT_EQ(mirror.size(), diffuse.size());
  double sum_mirror = 0, sum_diffuse = 0;
  for (std::size_t v = 0; v < mirror.size(); ++v) {
    sum_mirror += mirror[v];
    sum_diffuse += diffuse[v];
    EXPECT_LE(mirror[v], diffuse[v] + 1e-6f) << "vertex " << v;  // never darker
  }
  std::printf("summed ground shadow: mirror sphere %.3f, diffuse sphere %.3f\n", sum_mirror,
              sum_diffuse);
  EXPECT_LT(sum_mirror, 0.85 * sum_diffuse);
  EXPECT_GT(sum_mirror, 0.2 * sum_diffuse);  // the pawn's shadow and the rays sent down stay
}

TEST(SceneObjects, LambertOnlyOrGroundOffAddsNoReceiver) {
  ServiceConfig config;
  config.ground.enabled = false;
  EXPECT_EQ(make_scene_objects(config.objects, config.ground).size(), 2u);
  ObjectConfig plain;  // lambert
  config.ground.enabled = true;
  EXPECT_EQ(make_scene_objects({plain}, config.ground).size(), 1u);
}

}  // namespace
}  // namespace probeless
