#pragma once
// Temporal stabilisation of the occlusion matte (thesis 3.6, future work; issue #19 item 3):
// the previous frame's matte, re-projected into the current frame with the camera's motion
// and the depth, is blended into the current matte where colour and depth say the pixel
// still shows the same surface, and not where they changed (a moving hand leaves no trail).
// docs/occlusion.md "Temporal stabilisation" has the measurements behind the defaults.
#include "core/camera/pinhole.hpp"
#include "core/pose.hpp"

namespace probeless::occlusion {

struct StabiliserParams {
  // Weight of the history where nothing changed: an exponential average whose steady-state
  // variance for independent per-frame noise is (1 - w) / (1 + w) of one frame's (0.6: a
  // quarter). On the sim's tabletop rig 0.5 took cvf's temporal noise down 46 % and 0.6 55 %,
  // MSE down 13 % either way (docs/occlusion.md "Temporal stabilisation").
  float history_weight = 0.6f;
  // Colour change (Euclidean RGB, 8-bit / 255) at which the history's weight reaches 0; it
  // falls as 1 - (d / colour_range)^2. 0.1 = 26 levels: several times the sim camera's noise
  // after gamma, well below a hand against a table (docs/occlusion.md).
  float colour_range = 0.1f;
  // Depth change beyond which the pixel shows another surface: absolute + relative (the
  // CVF's 15 mm depth tolerance plus 2 % for the Kinect model's axial noise at range).
  float depth_tolerance_mm = 15.f;
  float depth_tolerance_rel = 0.02f;
  // A blended matte within `snap` of 0 or 1 becomes exactly 0 or 1. The average approaches
  // 0 and 1 only geometrically (x0.6 a frame: 13 frames from 1 to within 1/512), and every
  // fractional pixel costs the foreground estimate a window search: in `bench pipeline` the
  // tails took its work from ~3.5 to ~5.8 ms a frame; with the snap ~1.6. 1/512 moves an
  // 8-bit composite by less than half a level (docs/occlusion.md "Temporal stabilisation").
  float snap = 1.f / 512.f;
  // colour_range where only one of the two frames measured depth there: depth cannot say
  // whether the surface changed (a sensor hole flickering on a still surface, or the edge of
  // something without depth), so colour must, closer. Near occluders are marked in the depth
  // the matte hands on (OcclusionMethod::judged_depth(): cores and rims at kNearHoleDepthMm)
  // and compared pixel for pixel, so this range is for the other holes. On the sim, cvf ->
  // cvf+stab with 0.025 against 0.1: near hand MSE +6.9 % / +10.3 %, noise x0.72 / x0.73;
  // arm only -11.0 % / +0.3 %, x0.60 / x0.61 (docs/occlusion.md "Temporal stabilisation").
  float unconfirmed_colour_range = 0.025f;
  // The weight where depth is measured in both frames and agrees (the surface is confirmed,
  // not only its colour), and no near occluder is marked. What is left after the 0.6 average
  // on the sim is mostly matte errors that change slowly or move with the arm, which no
  // average removes; a heavier one where the scene is confirmed still takes a little more:
  // 0.85 against 0.6 (with the near-occluder rule below): arm only x0.556 -> x0.535
  // of cvf's temporal noise (seed 2: x0.549 -> x0.532), near hand x0.737 -> x0.730, MSE
  // within 0.6 points (docs/occlusion.md "Temporal stabilisation", 2026-12-08). Last in the
  // struct, as the next one, so that positional initialisers of the older fields still hold.
  float confirmed_history_weight = 0.85f;
  // The weight on a marked near occluder (OcclusionMethod::judged_depth(): cores and rims at
  // kNearHoleDepthMm, compared pixel for pixel), where history may only lower the matte: a
  // surface nearer than the sensor's range is in front of every virtual object, so its
  // history can say "hidden" but never "visible". Without that rule the rim CVF judged
  // visible was carried into the hand as it moved (error maps of the sim's near hand, frames
  // 5-12): near hand MSE +6.9 % over cvf; with it and 0.6 -15.2 %, with 0.9 -19.5 %
  // (0.95: -20.0 %; the rule holds the lowest value longer as the weight rises).
  float near_occluder_history_weight = 0.9f;
};

// Where the current frame's pixels were in the previous frame: the colour camera's
// intrinsics and T_prev_curr (current camera frame -> previous camera frame, OpenCV axes,
// metres); identity when the motion is unknown.
struct StabiliserMotion {
  PinholeIntrinsics intrinsics;
  Pose T_prev_curr;
};

}  // namespace probeless::occlusion
