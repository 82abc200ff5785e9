#pragma once
// `trajectory=calibration` (docs/sim.md "Calibration views"): a scripted set of rig poses
// around the table's ChArUco board (sim_board.hpp) from which `probeless calibrate
// --recording` recovers both cameras' intrinsics and the rig extrinsics. Each pose is held
// for kCalibrationHoldS seconds, so a recording at 1 frame per second has one view per frame.
#include "core/pose.hpp"

namespace probeless::sim {

inline constexpr double kCalibrationHoldS = 1.0;
// The number of scripted poses; the script repeats after kCalibrationViews * hold seconds.
int calibration_view_count();
// T_world_rig of the pose held at world time t.
Pose calibration_rig_pose(double t);

// The sim's true rig geometry (make_sim_rig's calibration): T_rig_rgb and T_rig_fisheye.
Pose rgb_in_rig();
Pose fisheye_in_rig();

}  // namespace probeless::sim
