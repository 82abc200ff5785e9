#pragma once
// The light model, per fisheye frame (thesis ch. 5-6; docs/light-capture.md): the keyframe
// for the fisheye's position (KeyframeSet), the texel update through the camera model and the
// rig pose (converting only the raw pixels it reads), push-pull of unobserved texels, and the
// SH of the updated keyframe. Times its steps; the caller decides where the times go.
#include <map>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "core/frame.hpp"
#include "core/pose.hpp"
#include "core/sh.hpp"
#include "kernels/envmap/envmap_downsample.hpp"
#include "kernels/envmap/envmap_update.hpp"
#include "kernels/envmap/keyframe_set.hpp"
#include "kernels/envmap/push_pull.hpp"
#include "kernels/hdr/hdr_conversion.hpp"
#include "kernels/light/sh_projector.hpp"

namespace probeless::light {

struct LightEstimatorConfig {
  envmap::KeyframeConfig keyframes;
  envmap::UpdateParams update;
  // The conversion of the raw samples; its image circle, when left at radius 0, is the fisheye
  // model's (max_theta).
  HdrConversionParams hdr;
  // Parallax with a room proxy (docs/light-capture.md "Parallax"); none: distant light.
  std::optional<envmap::RoomBox> room;
  // With a room: the SH is of the keyframe reprojected to this point (the object's), not of
  // the keyframe as seen from its own position.
  std::optional<Eigen::Vector3d> sh_position;
  // The keyframe is box-averaged (or reprojected) to this before the SH projection.
  int sh_face_size = 32;
  // Wait for the queue after each stage so that last_timings() holds each stage's time (what
  // `bench light` reports); false: one wait, at the SH download.
  bool time_stages = true;
  // Push-pull and the SH after every frame (what `bench light` and the tests time); false: only
  // when sh_of_active() or download() asks. The service's 4 Hz snapshots are the only readers
  // of both, and push-pull leaves observed texels unchanged and fills the others from them
  // alone, so filling at the reader gives the same texels: 3.6 of the 9.5 CPU-ms per fisheye
  // frame at 192 px faces saved ~46 times a second (docs/performance.md).
  bool fill_every_frame = true;
};

// One step of process(): wall-clock time and the process's CPU time (all threads, the
// OpenCL runtime's included: on a shared, loaded machine it moves much less than wall-clock
// time, so `bench light` reports both).
struct LightStepTime {
  std::string_view step;  // "upload", "update", "push_pull", "sh" or "total"
  double wall_ms = 0;
  double cpu_ms = 0;
};

// The times of the last process() call.
struct LightTimings {
  std::vector<LightStepTime> steps;  // in order; empty unless time_stages
  LightStepTime total{"total"};      // the whole call
};

class LightEstimator {
 public:
  // fisheye: any core/camera model (its lookup table is built here, once: fisheye_lut.hpp).
  LightEstimator(ComputeContext& ctx, const CameraModel& fisheye, const Pose& T_rig_fisheye,
                 const LightEstimatorConfig& config = {});

  // One fisheye frame and T_world_rig at its timestamp. Returns the keyframe it updated.
  const envmap::Keyframe& process(const FisheyeFrame& frame, const Pose& T_world_rig);
  // The same with the rig pose interpolated to the frame's timestamp; false (nothing done)
  // when the trajectory does not cover it.
  bool process(const FisheyeFrame& frame, const Trajectory& rig);

  // SH (5 bands) of the keyframe last updated, after push-pull; seen from sh_position when
  // that and a room are configured.
  // With fill_every_frame = false it is the one sh_of_active() last computed.
  const ShRgb& sh() const { return sh_; }
  // Push-pull and the SH of the keyframe last updated, unless done since its last update.
  const ShRgb& sh_of_active();
  const envmap::KeyframeSet& keyframes() const { return keyframes_; }
  // Host copy of a keyframe's texels after push-pull (blocking).
  envmap::ImageRGBAF download(const envmap::Keyframe& keyframe);
  // Steps: upload, update (conversion included), push_pull, sh; and the total.
  const LightTimings& last_timings() const { return timings_; }
  // Switches LightEstimatorConfig::time_stages between frames (bench light alternates).
  void set_time_stages(bool on) { config_.time_stages = on; }

 private:
  ComputeContext& ctx_;
  std::shared_ptr<const envmap::FisheyeLut> fisheye_;
  Pose T_rig_fisheye_;
  LightEstimatorConfig config_;
  envmap::KeyframeSet keyframes_;
  envmap::EnvmapUpdate update_;
  envmap::PushPull push_pull_;
  envmap::EnvmapDownsample downsample_;
  ShProjector projector_;
  // With a room and sh_position: per keyframe id (Keyframe::id, stable), the table of its SH
  // seen from there.
  std::map<int, ShProjector> reprojected_;
  DeviceImage<std::uint16_t, 3> raw_;
  DeviceImage<float, 4> small_;
  envmap::ImageRGBAF small_host_;
  // Push-pull of a keyframe unless done since its last update (enqueues only).
  void fill(const envmap::Keyframe& keyframe);
  void project_sh(const envmap::Keyframe& keyframe);  // downsample, download (waits), SH

  ShRgb sh_;
  // Per keyframe id, its `updates` at its last push-pull; the SH's keyframe and `updates`.
  std::map<int, std::uint64_t> filled_at_;
  int sh_keyframe_ = -1;
  std::uint64_t sh_updates_ = 0;
  // keyframes_.dropped() when the maps above were last cleared of dropped keyframes' ids.
  std::uint64_t dropped_seen_ = 0;
  void forget_dropped_keyframes();
  LightTimings timings_;
};

}  // namespace probeless::light
