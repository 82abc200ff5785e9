// The moving-object judge end to end on one scene (docs/fusion.md), at small sizes so that it
// takes seconds: the report's shape, the fusion column (the CPU surfel fusion, run on the same
// frames; with the device map, the same numbers), and today's method as docs/fusion.md measured it
// at full size (the box hardly shown, so no removal).
#include "lab/eval/moving_scene_eval.hpp"

#include <gtest/gtest.h>

namespace probeless::eval {
namespace {

TEST(MovingSceneEval, BoxRemovedEndToEnd) {
  MovingSceneEvalOptions o;
  o.scene = sim::MovingScene::BoxRemoved;
  o.config.light_face_size = 64;
  o.sphere_image_size = 96;
  const MovingSceneReport r = evaluate_moving_scene(o);
  EXPECT_EQ(r.scene, "box_removed");
  EXPECT_TRUE(r.fusion_implemented);
  EXPECT_EQ(r.with_fusion.source, EnvironmentSource::SurfelFusion);
  EXPECT_EQ(r.without_fusion.source, EnvironmentSource::ColourFillRoomBox);
  // The same frames and snapshots both ways; the fusion's column is its own run.
  EXPECT_EQ(r.with_fusion.fisheye_frames, r.without_fusion.fisheye_frames);
  EXPECT_EQ(r.with_fusion.snapshots, r.without_fusion.snapshots);
  EXPECT_EQ(r.with_fusion.near_object_pixels, r.without_fusion.near_object_pixels)
      << "the mask is the truth's, the same for both";
  EXPECT_NE(r.with_fusion.near_object_rel_rmse, r.without_fusion.near_object_rel_rmse);
  const SceneMetrics& m = r.without_fusion;
  EXPECT_EQ(m.fisheye_frames, 165);  // 5.5 s at 30 fps
  EXPECT_EQ(m.snapshots, 17);        // from 1.0 s, every 0.267 s
  ASSERT_EQ(m.events.size(), 1u);
  const EventResult& e = m.events[0];
  EXPECT_EQ(e.event.kind, sim::SceneEvent::Kind::Removal);
  EXPECT_GT(e.mask_pixels, 100);
  ASSERT_FALSE(e.samples.empty());
  EXPECT_NEAR(e.samples.front().t_s, 1.6, 1e-3) << "the first after the reference (1.333 s)";
  EXPECT_FALSE(m.arrival_s.has_value()) << "no arrival in this scene";
  // The box is on the sphere's pixels until 2.0 s only.
  for (const SnapshotSample& s : m.samples)
    EXPECT_EQ(s.near_object_pixels > 0, s.t_s < 2.0) << "t = " << s.t_s;
  EXPECT_GT(m.near_object_rel_rmse, 0.5) << "today's method hardly shows the box";
  EXPECT_LT(m.whole_sphere_rel_rmse, 0.2);
}

// The fusion column with the OpenCL map and environment (kernels/fusion/surfel_map.hpp,
// surfel_environment.hpp) judges as with the CPU references: the device map is the reference's
// surfel for surfel up to float rounding (tests/kernels/fusion: positions within 3e-9 m on the
// sim) and the device environment the reference's texel for texel on the tests' scenes, so the
// numbers agree to 1e-6 relative (they came out identical at full size, docs/fusion.md).
TEST(MovingSceneEval, TheDeviceMapJudgesAsTheReference) {
  MovingSceneEvalOptions o;
  o.scene = sim::MovingScene::BoxRemoved;
  o.config.light_face_size = 64;
  o.sphere_image_size = 96;
  const MovingSceneReport reference = evaluate_moving_scene(o);
  o.fusion_map = FusionMap::Device;
  const MovingSceneReport device = evaluate_moving_scene(o);
  EXPECT_EQ(reference.fusion_map, FusionMap::Reference);
  EXPECT_EQ(device.fusion_map, FusionMap::Device);
  const SceneMetrics& r = reference.with_fusion;
  const SceneMetrics& d = device.with_fusion;
  EXPECT_NEAR(d.near_object_rel_rmse, r.near_object_rel_rmse, 1e-6 * r.near_object_rel_rmse);
  EXPECT_NEAR(d.whole_sphere_rel_rmse, r.whole_sphere_rel_rmse, 1e-6 * r.whole_sphere_rel_rmse);
  EXPECT_EQ(d.removal_s.has_value(), r.removal_s.has_value());
  ASSERT_EQ(d.events.size(), r.events.size());
  for (std::size_t e = 0; e < r.events.size(); ++e)
    EXPECT_NEAR(d.events[e].before_position, r.events[e].before_position, 1e-6);
}

}  // namespace
}  // namespace probeless::eval
