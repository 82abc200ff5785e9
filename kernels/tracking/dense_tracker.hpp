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

struct DenseTrackerParams {
  float min_depth_m = 0.3f;  // depth outside [min, max] is not used
  float max_depth_m = 4.0f;
};

struct TrackResult {
  TrackingState state = TrackingState::Off;
  // The colour camera's pose in the tracker's world: the first frame's camera (or the pose
  // given to reset()). Meaningful only when state == Tracking.
  Pose T_world_camera;
  double residual_rms = 0.0;     // photometric, intensity units, at the finest level
  double inlier_fraction = 0.0;  // valid, non-outlier pixels / valid pixels
  int keyframes = 0;             // kept for relocalisation
  bool new_keyframe = false;     // this frame became the reference
};

class DenseTracker {
 public:
  // `ctx` null: the plain C++ reference (tests, CPU-only evaluation); else the OpenCL stages.
  // `camera` is the colour camera (depth is registered to it); images must be its size.
  DenseTracker(ComputeContext* ctx, const PinholeIntrinsics& camera,
               DenseTrackerParams params = {});
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
