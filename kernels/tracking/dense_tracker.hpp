#pragma once
// Dense RGB-D camera tracking after Kerl, Sturm & Cremers, "Robust Odometry Estimation for
// RGB-D Cameras" (ICRA 2013), as the thesis used it (Walton 2019, 6.2.5): the pose of each
// frame by minimising photometric and depth residuals against a reference keyframe, coarse to
// fine over an image pyramid, with Student-t weights and a constant-velocity prior. The state
// machine (tracking / lost / relocalising) and keyframe switching live here too, so every
// consumer (the service, `eval tracking`, `bench tracking`) runs the same tracker.
// docs/tracking.md explains the method, its parameters and their sources.
#include <memory>
#include <string>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"
#include "core/time.hpp"

namespace probeless {
class ComputeContext;
}

namespace probeless::tracking {

enum class TrackingState { Off, Tracking, Lost, Relocalising };
const char* to_string(TrackingState state);

// Defaults and their sources: docs/tracking.md "The dense tracker".
struct DenseTrackerParams {
  float min_depth_m = 0.3f;  // depth outside [min, max] is not used
  float max_depth_m = 4.0f;

  // Pyramid: `levels` levels used, the finest at 1/2^finest_level of the frame (1: 320x240
  // for VGA, the time budget; 0 = full resolution).
  int levels = 4;
  int finest_level = 1;
  // Keyframe points per level: one per block, the pixel of largest intensity gradient with
  // valid depth (the block side follows from this budget).
  int max_points_per_level = 4800;
  int max_iterations = 10;        // Gauss-Newton iterations per level
  double min_update = 1e-4;       // stop a level when |xi| (rad, m) < this x 2^level
  float student_nu = 5.0f;        // degrees of freedom of the t-distribution (Kerl et al.)
  bool constant_velocity = true;  // predict from the last motion, else the last pose
  // Rolling shutter: the time from the first row's exposure to the last row's (seconds); 0 for
  // a global shutter. Each row is then seen from the camera turned by the motion model's
  // angular velocity over its time from the middle row (docs/tracking.md).
  double rolling_shutter_readout_s = 0.0;

  // Inliers: residual within these bounds (grey levels after the brightness model; metres of
  // point-to-plane distance at 1 m, scaled by depth squared as the sensor's noise).
  float photometric_inlier = 20.0f;
  float geometric_inlier_m = 0.04f;
  // Lost when fewer keyframe points land inside the frame, or fewer of them are inliers.
  float min_visible_fraction = 0.3f;
  float min_inlier_fraction = 0.4f;

  // A new keyframe when the current one is seen less or moved away (translation, rotation).
  float keyframe_min_visible = 0.7f;
  float keyframe_max_translation_m = 0.10f;
  float keyframe_max_rotation_deg = 10.0f;
  int max_keyframes = 8;  // kept for relocalisation, the oldest dropped first
};

struct TrackResult {
  TrackingState state = TrackingState::Off;
  // The colour camera's pose in the tracker's world: the first frame's camera (or the pose
  // given to reset()). Meaningful only when state == Tracking.
  Pose T_world_camera;
  double residual_rms = 0.0;      // photometric, grey levels after the brightness model
  double inlier_fraction = 0.0;   // of the keyframe points inside the frame (finest level)
  int keyframes = 0;              // kept for relocalisation
  int keyframe_id = -1;           // the reference's frame number since reset() (diagnostics)
  bool new_keyframe = false;      // this frame became the reference
  bool relocalised = false;       // tracking resumed against a kept keyframe on this frame
  bool revisited = false;         // an older kept keyframe became the reference again (no new one)
  double visible_fraction = 0.0;  // keyframe points that land inside this frame
  double exposure_gain = 1.0;     // brightness model: I_frame = gain * I_keyframe + bias
  double exposure_bias = 0.0;
  int iterations = 0;        // Gauss-Newton iterations, every level (and every attempt)
  double pyramid_ms = 0.0;   // time to build this frame's pyramid
  double align_ms = 0.0;     // alignment (and relocalisation attempts)
  double keyframe_ms = 0.0;  // keyframe precomputation when this frame became one
};

class DenseTracker {
 public:
  // `ctx` null: the plain C++ reference (tests, CPU-only evaluation); else the OpenCL stages.
  // `camera` is the colour camera (depth is registered to it); images must be its size.
  DenseTracker(ComputeContext* ctx, const PinholeIntrinsics& camera,
               DenseTrackerParams params = {});
  // With the colour camera's lens distortion: the finest level is undistorted (depth is taken
  // as registered to the distorted colour image, as the Kinect's registration delivers it).
  DenseTracker(ComputeContext* ctx, const PinholeCamera& camera, DenseTrackerParams params = {});
  ~DenseTracker();
  DenseTracker(const DenseTracker&) = delete;
  DenseTracker& operator=(const DenseTracker&) = delete;

  // Depth in millimetres, 0 = unknown. Throws std::invalid_argument on a size mismatch.
  TrackResult track(const ImageRGB8& colour, const DepthImage& depth_mm, TimestampNs timestamp_ns);
  // Forget every keyframe; the next frame starts again at `T_world_camera`.
  void reset(const Pose& T_world_camera = Pose::identity());
  TrackingState state() const;
  bool uses_device() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace probeless::tracking
