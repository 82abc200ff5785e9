#pragma once
// `probeless eval tracking` (docs/tracking.md "Evaluation"): every method on the same frames
// of one sequence, in one process, each frame read once and handed to each method in turn;
// then ATE, RPE and the registration error against the sequence's truth
// (lab/eval/trajectory_metrics.hpp), and the time each method took per frame.
#include <optional>
#include <string>
#include <vector>

#include "lab/eval/tracking_dataset.hpp"
#include "lab/eval/tracking_methods.hpp"
#include "lab/eval/trajectory_metrics.hpp"

namespace probeless::eval {

struct TrackingMethodReport {
  std::string name;
  std::optional<double> ate_rmse_m;
  std::optional<double> rpe_t_m, rpe_r_deg;  // RMSE over 1 s pairs
  int rpe_pairs = 0;
  double reg_px_p50 = 0, reg_px_p95 = 0;
  int reg_frames = 0;             // frames whose true projection of the anchor is inside the image
  double p50_ms = 0, p99_ms = 0;  // per frame, the first (initialising) frame excluded
  int lost_frames = 0;
  std::vector<PosePair> poses;      // per frame: the tracked pose and the truth
  std::vector<TrackingStep> steps;  // per frame: lost, the reference keyframe
};

struct TrackingEvalReport {
  std::string sequence;
  std::string camera;  // intrinsics' source and undistortion
  int frames = 0;
  double anchor_depth_m = 0;            // median depth of the first frame's central 64x64 window
  PinholeIntrinsics camera_intrinsics;  // the ideal pinhole the metrics project through
  std::vector<TrackingMethodReport> methods;
};

// Throws std::invalid_argument for an unknown method, a sequence without frames or a first
// frame without depth at its centre; std::runtime_error when a frame cannot be read.
TrackingEvalReport evaluate_tracking(TrackingSequence& sequence,
                                     const std::vector<std::string>& methods,
                                     const TrackingDepthRange& range, ComputeContext* ctx);

// The median of the valid depths (mm, 0 = unknown) in the `window` x `window` square at the
// image centre, in metres; nullopt when none is valid.
// Writes DIR/<method>.txt (tracked) and DIR/groundtruth.txt in TUM's trajectory format
// ("timestamp tx ty tz qx qy qz qw", seconds), for TUM's own evaluate_ate.py / evaluate_rpe.py
// and plots. Throws std::runtime_error when a file cannot be written.
void write_tum_trajectories(const TrackingEvalReport& report, const std::string& dir);

// Writes one CSV row per frame and method (`eval tracking --per-frame`): frame, timestamp,
// method, lost, the dense tracker's reference keyframe, the registration error (empty where
// the truth does not see the anchor) and the rotation (deg) and translation (m) errors of
// the pose relative to the first frame against the truth's (the registration's anchoring,
// no alignment). Throws std::runtime_error when the file cannot be written.
void write_per_frame_csv(const TrackingEvalReport& report, const std::string& path);

std::optional<double> central_median_depth_m(const DepthImage& depth_mm, int window = 64);

}  // namespace probeless::eval
