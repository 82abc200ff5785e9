#pragma once
// Trajectory error measures of `probeless eval tracking` (docs/tracking.md "Evaluation"):
// ATE after a rigid alignment, RPE over fixed time steps (Sturm et al., "A Benchmark for the
// Evaluation of RGB-D SLAM Systems", IROS 2012, and its evaluate_ate.py / evaluate_rpe.py),
// and the registration error a user sees: how far a world-anchored point lands from where the
// ground truth puts it, in pixels. Poses are T_world_camera; estimate and truth are index
// aligned (one entry per frame).
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/camera/pinhole.hpp"
#include "core/pose.hpp"
#include "core/time.hpp"

namespace probeless::eval {

// The rigid motion T minimising sum |dst_i - T src_i|^2 (Umeyama 1991 without the scale: a
// metric RGB-D trajectory must not be rescaled to look better). Throws std::invalid_argument
// for fewer than 3 pairs or sizes that differ.
Pose umeyama_rigid(const std::vector<Eigen::Vector3d>& src,
                   const std::vector<Eigen::Vector3d>& dst);

struct PosePair {
  TimestampNs timestamp_ns = 0;
  Pose estimate;
  std::optional<Pose> truth;  // frames without ground truth take no part
};

// Absolute trajectory error: RMSE of the camera positions after aligning the estimate onto
// the truth with umeyama_rigid over every frame that has truth. nullopt below 3 such frames.
std::optional<double> ate_rmse_m(const std::vector<PosePair>& frames);

struct RelativePoseError {
  double translation_rmse_m = 0;
  double rotation_rmse_deg = 0;
  int pairs = 0;
};

// Relative pose error over pairs (i, j) whose time difference is closest to `delta_s`, as
// evaluate_rpe.py --fixed_delta --delta_unit s: for each i, j = the frame whose timestamp is
// closest to t_i + delta; the pair is dropped when j is the last frame (there the wanted time
// lay beyond the end) or when either frame lacks truth. Error E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j)
// (Q truth, P estimate); translational and rotational RMSE over the pairs (evaluate_rpe.py's
// "rmse" rows). nullopt without any pair.
std::optional<RelativePoseError> relative_pose_error(const std::vector<PosePair>& frames,
                                                     double delta_s = 1.0);

// The registration error of a world-anchored point: `point_first` is given in the first
// frame's camera; each frame projects it with the estimated and with the true pose, both
// relative to their own first frame (no alignment), through `camera` (ideal pinhole). One
// value per frame whose true projection lies in front of the camera and inside the image;
// an estimated projection behind the camera counts as the image diagonal. The first frame
// must have truth (std::invalid_argument otherwise).
std::vector<double> registration_px(const std::vector<PosePair>& frames,
                                    const PinholeIntrinsics& camera,
                                    const Eigen::Vector3d& point_first);
// The same per frame, index aligned with `frames`: nullopt where the frame has no truth or
// its true projection is behind the camera or outside the image (`eval tracking --per-frame`).
std::vector<std::optional<double>> registration_px_per_frame(const std::vector<PosePair>& frames,
                                                             const PinholeIntrinsics& camera,
                                                             const Eigen::Vector3d& point_first);

// q-quantile (q in [0, 1]) by linear interpolation between order statistics (numpy's
// default); 0 for an empty set.
double quantile(std::vector<double> values, double q);

}  // namespace probeless::eval
