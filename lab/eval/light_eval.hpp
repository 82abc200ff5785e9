#pragma once
// `probeless eval light --source sim`: the light estimator on the synthetic rig's slow orbit,
// its keyframe compared with the sim's ground truth (docs/light-capture.md "eval light").
#include <array>
#include <optional>
#include <string>

#include "base/stage_stats.hpp"
#include "drivers/sim/sim_world.hpp"
#include "kernels/light/light_estimator.hpp"

namespace probeless::light {

struct LightEvalOptions {
  double seconds = 2.0;  // sim time
  std::string sim_spec;  // extra sim options (after realtime=0)
  LightEstimatorConfig estimator;
  // Parallax with the sim's room box (estimator.room is set from drivers/sim's geometry), and
  // the comparisons at other positions through keyframe reprojection; false: distant light,
  // the keyframe's directions compared as they are.
  bool room_box = true;
  int compare_face_size = 32;  // the truth cubemap's resolution
  // Non-empty: write compare.png there: the keyframe and the truth at its position, the
  // keyframe reprojected to the object and the truth there, the same at the last capture;
  // faces top to bottom in GL order, log-scaled; unobserved texels darkened.
  std::string dump_dir;
  // Non-empty: light capture runs with this rig calibration (a TOML `probeless calibrate`
  // wrote) instead of the sim's true one: its fisheye model and its fisheye pose, placed in the
  // sim's rig through its colour camera (what tracking observes), so errors in the recovered
  // extrinsics reach the capture as they would on a real rig. Its fisheye must have the sim's
  // frame size.
  std::string calibration_file;
};

struct FaceError {
  int observed = 0;                     // compared texels (fully observed at keyframe resolution)
  std::optional<double> relative_rmse;  // sqrt(sum |est - true|^2 / sum |true|^2), RGB
};

struct TruthComparison {
  std::string truth;  // what the keyframe is compared with
  std::array<FaceError, 6> faces;
  FaceError all;
  double sh25_relative_error = 0;  // |c_est - c_true| / |c_true| over 25 x 3 coefficients
  double sh9_relative_error = 0;
};

struct LightEvalReport {
  int frames = 0;
  int keyframes = 0;
  int keyframe_id = -1;
  double keyframe_distance_m = 0;  // from the keyframe to the light probe position
  double scale = 0;                // converted value -> sim radiance
  std::string rule;
  bool room_box = false;  // parallax and reprojection through the sim's room box
  // FrameTruth::light, seen from light_probe_position(), against the keyframe reprojected
  // there (with the room box; else the keyframe's directions as they are)
  TruthComparison at_probe;
  TruthComparison at_probe_unreprojected;  // ... against the keyframe's directions as they are
  TruthComparison at_keyframe;             // the same room rendered from the keyframe's position
  // ... and from the fisheye's last position, against the keyframe reprojected there (the
  // Kalman filter weighs recent frames most)
  TruthComparison at_last_capture;
  double keyframe_to_last_capture_m = 0;
  int settle_cycles = 0;
  TimingSummary total;
};

LightEvalReport evaluate_light_sim(const LightEvalOptions& options);

// The comparison itself (unit-tested): est and truth are m x 6m radiance images at the same
// resolution; `observed` marks the compared texels of est.
TruthComparison compare_cubemaps(const envmap::ImageRGBAF& est, const envmap::ImageRGBAF& truth,
                                 const std::vector<bool>& observed);
// The sim's room seen from `position` under `lamp_state` as n x 6n texels (the keyframe
// layout), one ray per texel centre; alpha 1. Box-average a larger one for a smoother truth.
// With `objects` (a moving-object scene's, sim_moving_scene.hpp) they are in the room too, and
// `object_hits` (when given) gets 1 in RGB where a texel's ray meets one of them first, else
// 0: box-averaged, each texel's share of the object (the near-object mask of `eval render
// --scene`, docs/fusion.md).
envmap::ImageRGBAF render_truth_cubemap(const std::shared_ptr<const sim::SimWorld>& world,
                                        const Eigen::Vector3d& position, int lamp_state, int n,
                                        const sim::Occluder* objects = nullptr,
                                        envmap::ImageRGBAF* object_hits = nullptr);
// Box-average of an n x 6n keyframe to m-px faces; a texel is observed when all of its n/m
// x n/m sources are (alpha > 0).
envmap::ImageRGBAF average_observed(const envmap::ImageRGBAF& texels, int m,
                                    std::vector<bool>& observed);

}  // namespace probeless::light
