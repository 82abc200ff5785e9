// The surfel map's reference on the sim's box_appears scene (drivers/sim/sim_moving_scene.hpp,
// docs/fusion.md): the real path's frames, with the sensor's Kinect-like depth noise, the
// truth poses and the rig calibration, around the point where the judge stands its sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "drivers/sim/sim_moving_scene.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "kernels/fusion/surfel_map_reference.hpp"

namespace probeless::fusion {
namespace {

// Whether a surfel lies in the scene's box at world time t: 1 cm around it, and from 2 cm above
// its base so that the table's noise (sigma_z ~4 mm at 1.7 m) under it does not count.
auto in_box_at(sim::MovingScene scene, double t) {
  const sim::Occluder objects = sim::moving_scene_objects(scene, t);
  EXPECT_EQ(objects.boxes.size(), 1u);
  Eigen::Vector3f lo = objects.boxes.at(0).lo - Eigen::Vector3f::Constant(0.01f);
  const Eigen::Vector3f hi = objects.boxes.at(0).hi + Eigen::Vector3f::Constant(0.01f);
  lo.z() = objects.boxes.at(0).lo.z() + 0.02f;
  return [lo, hi](const Surfel& s) {
    return (s.position.array() >= lo.array()).all() && (s.position.array() <= hi.array()).all();
  };
}

TEST(SurfelMapSim, TheBoxThatAppearsIsFusedAndBecomesStable) {
  // 15 frames before the box appears at 2.0 s and 15 from then on, at 30 frames/s.
  Rig rig = sim::make_sim_rig(
      sim::parse_sim_options("realtime=0,trajectory=static,scene=box_appears,start=1.5,frames=30"));
  const auto in_box = in_box_at(sim::MovingScene::BoxAppears, 2.0);

  SurfelMapParams params;
  params.region_centre = sim::light_probe_position().cast<float>();
  params.region_radius_m = 0.5f;  // the table around the sphere, the box 24 cm from it
  SurfelMap map(params);
  const PinholeIntrinsics& k = rig.calibration.rgb.intrinsics();
  int first_with_box = -1, stable_after = -1;
  for (int frame = 0; frame < 30; ++frame) {
    RgbdFrame f;
    ASSERT_EQ(rig.rgbd->read(f, std::chrono::milliseconds(10000)), ReadResult::Frame);
    ASSERT_TRUE(f.truth && f.truth->rig_pose);
    const Pose T_world_rgb = *f.truth->rig_pose * rig.calibration.T_rig_rgb;
    const auto stats = map.integrate(f.depth, f.colour, {1, 1, 1}, k, T_world_rgb, frame);
    const double t = 1.5 + frame / 30.0;
    const bool box_there = t >= 2.0 - 1e-6;
    if (box_there && first_with_box < 0) first_with_box = frame;
    // On the box: all of them, and those born on the frame it appeared (its edges keep a few
    // unstable newcomers, and a tenth of the first ones are edge pixels seen now and then, so
    // "stable" is said of 80 % of the first ones).
    std::size_t on_box = 0, stable_on_box = 0, first = 0, stable_first = 0;
    for (const Surfel& s : map.surfels()) {
      if (!in_box(s)) continue;
      ++on_box;
      stable_on_box += map.is_stable(s);
      if (s.created_frame == first_with_box) {
        ++first;
        stable_first += map.is_stable(s);
      }
    }
    if (!box_there) {
      EXPECT_EQ(on_box, 0u) << "frame " << frame << ": nothing there yet";
    } else {
      EXPECT_GT(on_box, 1000u) << "frame " << frame << ": the box's front and top, ~1500 px";
      if (stable_after < 0 && stable_first >= 0.8 * static_cast<double>(first))
        stable_after = frame - first_with_box;
    }
    std::printf(
        "frame %2d t %.3f s: %zu surfels (%zu stable), box %zu (%zu stable; of the first "
        "%zu, %zu); fused %zu born %zu violations %zu unstable gone %zu\n",
        frame, t, map.size(), map.stable_count(), on_box, stable_on_box, first, stable_first,
        stats.fused, stats.born, stats.removed_violation, stats.removed_unstable);
  }
  EXPECT_EQ(first_with_box, 15) << "in the map on the frame it appears";
  std::printf("box: in the map from frame %d, 80 %% of its first surfels stable %d frames later\n",
              first_with_box, stable_after);
  ASSERT_GE(stable_after, 0) << "never 80 % stable";
  EXPECT_GE(stable_after, 9) << "not before ten sightings";
  EXPECT_LE(stable_after, 14) << "within the 15 frames (0.5 s) after it appeared";
}

// What the sensor sees through goes at once (6.2.6). Behind the box's lower front the view
// falls past the table's back edge to the back wall 3.6 m away, and along that depth jump the
// Kinect-like sensor model leaves holes (truth depth 3.6 m, measured 0): surfels in front of
// them stay, for the colour-violation rule of item 3 [6.2.6] to remove.
TEST(SurfelMapSim, TheRemovedBoxLeavesTheMapOnTheFrameItGoesWhereThereIsDepth) {
  Rig rig = sim::make_sim_rig(
      sim::parse_sim_options("realtime=0,trajectory=static,scene=box_removed,start=1.5,frames=20"));
  const auto in_box = in_box_at(sim::MovingScene::BoxRemoved, 1.9);
  SurfelMapParams params;
  params.region_centre = sim::light_probe_position().cast<float>();
  params.region_radius_m = 0.5f;
  SurfelMap map(params);
  const PinholeIntrinsics& k = rig.calibration.rgb.intrinsics();
  std::size_t before = 0;
  for (int frame = 0; frame < 20; ++frame) {
    RgbdFrame f;
    ASSERT_EQ(rig.rgbd->read(f, std::chrono::milliseconds(10000)), ReadResult::Frame);
    const Pose T_world_rgb = *f.truth->rig_pose * rig.calibration.T_rig_rgb;
    const auto stats = map.integrate(f.depth, f.colour, {1, 1, 1}, k, T_world_rgb, frame);
    const Pose T_rgb_world = T_world_rgb.inverse();
    std::size_t on_box = 0, stable_on_box = 0, over_depth = 0;
    for (const Surfel& s : map.surfels()) {
      if (!in_box(s)) continue;
      ++on_box;
      stable_on_box += map.is_stable(s);
      const Eigen::Vector3d pc = T_rgb_world * s.position.cast<double>();
      const auto u = static_cast<int>(std::floor(k.fx * pc.x() / pc.z() + k.cx + 0.5));
      const auto v = static_cast<int>(std::floor(k.fy * pc.y() / pc.z() + k.cy + 0.5));
      over_depth += f.depth.contains(u, v) && f.depth.at(u, v) != 0;
    }
    if (frame == 14) {
      EXPECT_GT(stable_on_box, 1000u) << "stable before it goes";
      before = on_box;
    }
    if (frame < 15) {
      EXPECT_GT(on_box, 1000u) << "frame " << frame;
      continue;
    }
    // 2.0 s: gone wherever the sensor sees what is behind it.
    // A few at the box's foot stay, the table behind them within violation_margin_m.
    EXPECT_LE(static_cast<double>(over_depth), 0.01 * static_cast<double>(before))
        << "frame " << frame;
    EXPECT_LT(static_cast<double>(on_box), 0.15 * static_cast<double>(before)) << "frame " << frame;
    if (frame == 15) {
      EXPECT_GT(stats.removed_violation, 1000u);
      std::printf("removed box: %zu of %zu surfels left, %zu of them where there is depth\n",
                  on_box, before, over_depth);
    }
  }
}

// The reference's cost on the sim's view of box_appears with the judge's region (0.5 m around
// the sphere: ~19 000 of the 307 200 pixels): run with --gtest_also_run_disabled_tests.
TEST(SurfelMapSim, DISABLED_CostBoxAppears) {
  Rig rig = sim::make_sim_rig(
      sim::parse_sim_options("realtime=0,trajectory=static,scene=box_appears,start=1.5,frames=30"));
  SurfelMapParams params;
  params.region_centre = sim::light_probe_position().cast<float>();
  params.region_radius_m = 0.5f;
  SurfelMap map(params);
  std::vector<double> ms;
  for (int frame = 0; frame < 30; ++frame) {
    RgbdFrame f;
    ASSERT_EQ(rig.rgbd->read(f, std::chrono::milliseconds(10000)), ReadResult::Frame);
    const Pose T_world_rgb = *f.truth->rig_pose * rig.calibration.T_rig_rgb;
    const auto t0 = std::chrono::steady_clock::now();
    map.integrate(f.depth, f.colour, {1, 1, 1}, rig.calibration.rgb.intrinsics(), T_world_rgb,
                  frame);
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  std::printf("surfel map reference, sim box_appears, region 0.5 m, %zu surfels: p50 %.1f ms\n",
              map.size(), ms[ms.size() / 2]);
}

}  // namespace
}  // namespace probeless::fusion
