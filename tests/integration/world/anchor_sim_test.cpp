// World anchoring against the sim's ground truth (issue #17's bar): with the board on the
// table (`sim:board=1`), the marker's world within 5 mm and 0.5 degrees of where the board
// truly is; with `anchor = floor`, z up within 1 degree. Tracking is the sim's truth here, so
// what is measured is the anchor alone.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>

#include "app/world/rig_localiser.hpp"
#include "app/world/world_anchor.hpp"
#include "drivers/rig_factory.hpp"
#include "drivers/sim/sim_rig.hpp"

namespace probeless::world {
namespace {

using namespace std::chrono_literals;

struct AnchorError {
  double max_mm = 0, max_deg = 0;
  int located = 0, frames = 0;
};

// The anchored world in the sim's world as the localiser has it after each frame:
// T_sim_world = T_sim_rig (truth) * T_world_rig^-1, against `truth`.
AnchorError run(const std::string& spec, const WorldConfig& world, const Pose& truth, int frames,
                bool z_only = false) {
  Rig rig = open_rig(spec);
  TrackingConfig tracking;
  tracking.method = "truth";
  RigLocaliser localiser(tracking, world, rig.calibration, nullptr);
  AnchorError e;
  RgbdFrame frame;
  for (int i = 0; i < frames; ++i) {
    if (rig.rgbd->read(frame, 5s) != ReadResult::Frame) break;
    ++e.frames;
    const auto T_world_rig = localiser.locate(frame);
    if (!T_world_rig) continue;
    ++e.located;
    const Pose T_sim_world = *frame.truth->rig_pose * T_world_rig->inverse();
    const Eigen::Vector3d z = T_sim_world.rotation * Eigen::Vector3d::UnitZ();
    const double deg = z_only ? std::acos(std::min(1.0, z.z())) * 180 / M_PI
                              : T_sim_world.rotation.angularDistance(truth.rotation) * 180 / M_PI;
    e.max_deg = std::max(e.max_deg, deg);
    if (!z_only)
      e.max_mm = std::max(e.max_mm, (T_sim_world.translation - truth.translation).norm() * 1e3);
  }
  return e;
}

TEST(AnchorSim, TheBoardAnchorsTheWorldWithin5mmAndHalfADegree) {
  WorldConfig world;
  world.anchor = "marker";
  world.marker = sim::board_spec();
  // 1 s of the tabletop swing, at three points of it (start = 0, 5, 15 s: the rig at the
  // middle and both ends of its +-20 degree arc).
  for (const char* start : {"0", "5", "15"}) {
    const AnchorError e =
        run(std::string("sim:realtime=0,trajectory=tabletop,board=1,start=") + start, world,
            sim::board_world_pose(), 30);
    std::cout << "marker anchor, start " << start << " s: " << e.located << "/" << e.frames
              << " frames, max " << e.max_mm << " mm, " << e.max_deg << " deg\n";
    // Detection runs on its own thread: the first frame or two go by before the first
    // sighting is back (nothing is drawn meanwhile).
    EXPECT_GE(e.located, e.frames - 3) << "the board is in view all along";
    EXPECT_LT(e.max_mm, 5.0);
    EXPECT_LT(e.max_deg, 0.5);
  }
}

// The tracker's world slips by 3 cm (drift, a relocalisation) while the board stays in view:
// the world follows the board back, at most max_step_mm per frame. The slip starts once the
// world has been found and held for a few frames, so the test does not depend on which early
// frame the detector first finds the board in (one suite run under load found the world
// already near the slipped one and "failed" for a glide it never had to make).
TEST(AnchorSim, ReanchoringGlidesAtTheBoundedRate) {
  WorldConfig world;
  world.anchor = "marker";
  world.marker = sim::board_spec();
  Rig rig = open_rig("sim:realtime=0,trajectory=tabletop,board=1");
  WorldAnchor anchor(world, rig.calibration);
  Pose slip;
  slip.translation = Eigen::Vector3d(0.03, 0, 0);
  constexpr int kSettle = 5;   // frames the found world is held before the slip
  constexpr int kFrames = 30;  // slipped frames
  std::optional<Pose> previous, before_slip;
  int found_at = -1;
  double max_step_mm = 0, detect_ms = 0, update_ms = 0;
  RgbdFrame frame;
  for (int i = 0; found_at < 0 || i < found_at + kSettle + kFrames; ++i) {
    if (found_at < 0) {
      ASSERT_LT(i, 10) << "the world was not found in the first frames: the board is in view";
    }
    ASSERT_EQ(rig.rgbd->read(frame, 5s), ReadResult::Frame);
    // The sim's world is the tracker's until the slip; from then on the tracker has it 3 cm off.
    const bool slipped = found_at >= 0 && i >= found_at + kSettle;
    Pose T_tracker_camera = *frame.truth->rig_pose * rig.calibration.T_rig_rgb;
    if (slipped) T_tracker_camera = slip * T_tracker_camera;
    const auto t0 = std::chrono::steady_clock::now();
    const auto T_world_tracker = anchor.update(frame, T_tracker_camera);
    const auto t1 = std::chrono::steady_clock::now();
    anchor.wait_for_detection();  // each sighting applied on the next frame, deterministically
    update_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
    detect_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
    if (!T_world_tracker) continue;
    if (found_at < 0) found_at = i;
    if (!slipped) before_slip = T_world_tracker;
    if (previous)
      max_step_mm = std::max(max_step_mm, world_step_m(*previous, *T_world_tracker) * 1e3);
    previous = T_world_tracker;
  }
  // Where the world should end up: the board's, in the slipped tracker's world.
  const Pose expected = (slip * sim::board_world_pose()).inverse();
  const double left_mm = world_step_m(*previous, expected) * 1e3;
  const double moved_mm = world_step_m(*before_slip, *previous) * 1e3;
  std::cout << "re-anchoring 30 mm (world found at frame " << found_at << "): largest step "
            << max_step_mm << " mm/frame, moved " << moved_mm << " mm, " << left_mm
            << " mm left after " << kFrames << " frames; on the processing thread "
            << update_ms / (found_at + kSettle + kFrames) << " ms/frame, the detector's wait "
            << detect_ms / (found_at + kSettle + kFrames) << " ms/frame\n";
  EXPECT_LE(max_step_mm, world.max_step_mm + 0.05);
  EXPECT_GT(moved_mm, 20.0) << "it does follow the board";
  EXPECT_LT(left_mm, 5.0);
}

TEST(AnchorSim, WithoutTheBoardTheWorldIsNotFoundAndNothingIsDrawn) {
  WorldConfig world;
  world.anchor = "marker";
  world.marker = sim::board_spec();
  const AnchorError e =
      run("sim:realtime=0,trajectory=tabletop", world, sim::board_world_pose(), 5);
  EXPECT_EQ(e.frames, 5);
  EXPECT_EQ(e.located, 0);
}

// The tabletop view, where the table fills the lower picture. (The sim's level views graze the
// table at 10-17 degrees and see the floor only beyond it: there the plane is found with
// z 1.2-5 degrees off, docs/tracking.md "World anchoring", limits.)
TEST(AnchorSim, TheFloorAnchorsZUpWithinOneDegree) {
  WorldConfig world;
  world.anchor = "floor";
  for (const char* start : {"0", "5", "15"}) {
    const std::string spec = std::string("sim:realtime=0,trajectory=tabletop,start=") + start;
    const AnchorError e = run(spec, world, Pose::identity(), 5, true);
    std::cout << "floor anchor, " << spec << ": " << e.located << "/" << e.frames
              << " frames, z off by " << e.max_deg << " deg\n";
    EXPECT_EQ(e.located, e.frames) << spec;
    EXPECT_LT(e.max_deg, 1.0) << spec;
  }
}

}  // namespace
}  // namespace probeless::world
