// The service's light stage with [light] max_keyframes: keyframes dropped while it publishes.
#include "app/pipeline/light_capture.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <set>

#include "drivers/bracket/bracket_sequencer.hpp"
#include "drivers/sim/sim_rig.hpp"

namespace probeless {
namespace {

// Issue #20: past the cap the farthest keyframe goes, with its reprojection map and texels.
// Every snapshot published meanwhile must name a keyframe the set still holds and carry whole,
// finite texels; the stage's per-keyframe cache must never hold more than the set does.
TEST(LightCapture, SnapshotsStayValidWhileKeyframesAreDropped) {
  Rig rig = sim::make_sim_rig(
      sim::parse_sim_options("realtime=0,fisheye_size=256,trajectory=orbit,threads=1"));
  ASSERT_TRUE(rig.scene.room) << "the sim's room: the reprojection cache is what is checked";
  ServiceConfig config;
  config.light_face_size = 32;
  config.light_keyframe_distance_m = 0.03;  // a new keyframe every few frames of the orbit
  config.light_max_keyframes = 2;
  config.light_colour_fill = false;
  LightCapture capture(config, rig.calibration, rig.scene);
  ASSERT_TRUE(capture.initialise()) << capture.status().dump();

  BracketSequencer sequencer;
  FisheyeFrame frame;
  std::uint64_t seen = 0;
  int snapshots_after_a_drop = 0;
  for (int i = 0; i < 90; ++i) {
    rig.fisheye->set_next_exposure(sequencer.next());
    ASSERT_EQ(rig.fisheye->read(frame, std::chrono::seconds(5)), ReadResult::Frame);
    ASSERT_TRUE(capture.process(frame)) << capture.status().dump();
    const nlohmann::json s = capture.status();
    ASSERT_LE(s["keyframes"].get<int>(), 2) << "frame " << i;
    ASSERT_EQ(s["kept"].size(), s["keyframes"].get<std::size_t>());
    ASSERT_LE(s["reprojected_keyframes"].get<int>(), 2) << "a dropped keyframe's map outlived it";
    const auto snap = capture.latest_light();
    if (!snap || snap->version == seen) continue;
    seen = snap->version;
    std::set<int> kept;
    for (const auto& k : s["kept"]) kept.insert(k["id"].get<int>());
    EXPECT_TRUE(kept.count(snap->keyframe_id)) << "snapshot of keyframe " << snap->keyframe_id;
    ASSERT_EQ(snap->texels.width(), 32);
    ASSERT_EQ(snap->texels.height(), 6 * 32);
    for (float v : snap->texels.elements()) ASSERT_TRUE(std::isfinite(v));
    for (const auto& c : snap->sh.c) ASSERT_TRUE(c.allFinite());
    if (s["keyframes_dropped"].get<int>() > 0) ++snapshots_after_a_drop;
  }
  const nlohmann::json s = capture.status();
  EXPECT_GE(s["keyframes_dropped"].get<int>(), 3) << s.dump();
  EXPECT_GE(snapshots_after_a_drop, 3);
  EXPECT_EQ(s["max_keyframes"], 2);
}

}  // namespace
}  // namespace probeless
