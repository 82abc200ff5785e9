#pragma once
// The service's light stage (issue #5; docs/light-capture.md): its own thread takes every
// fisheye frame of the bracket cycle and updates the HDR environment-map keyframes and their
// SH through light::LightEstimator, on its own OpenCL queue so that it never waits for the
// RGB-D frame path (nor that path for it). In the service the rig pose at each fisheye frame
// is the processing thread's (tracked, anchored) poses interpolated to the fisheye timestamp,
// and keyframe updates pause while it is unknown (docs/tracking.md "Poses in the service").
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <stop_token>
#include <string>
#include <utility>
#include <vector>

#include "app/pipeline/light_pacing.hpp"
#include "app/pipeline/pose_history.hpp"
#include "app/pipeline/service_config.hpp"
#include "app/render/environment.hpp"
#include "app/service/heartbeat.hpp"
#include "base/stage_stats.hpp"
#include "core/calibration.hpp"
#include "core/frame.hpp"
#include "core/sh.hpp"
#include "drivers/source.hpp"
#include "kernels/envmap/envmap_types.hpp"
#include "kernels/envmap/keyframe_reprojection.hpp"

namespace probeless::envmap {
struct Keyframe;
}

namespace probeless {

// What the render stage lights the virtual objects with (issue #6): a host copy of the
// keyframe nearest to the objects, its SH, and the colour camera's exposure in the same
// radiance units. Immutable once published; a newer snapshot has a higher version.
struct LightSnapshot {
  std::uint64_t version = 0;
  TimestampNs timestamp_ns = 0;  // of the newest fisheye frame it includes
  int keyframe_id = -1;
  // Where `texels` are seen from: the keyframe's capture position, or with a room box
  // ([light] room) the objects' light point, the keyframe reprojected there (alpha 1 where
  // observed, else 0).
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  envmap::ImageRGBAF texels;  // n x 6n, envmap_types.hpp layout, after push-pull
  ShRgb sh;                   // 5 bands of `texels`, world frame (z up)
  // Fisheye radiance per unit of the colour camera's linear value, per channel
  // (kernels/hdr/colour_exposure.hpp); valid = false until a frame pair matched.
  Eigen::Vector3d colour_exposure = Eigen::Vector3d::Ones();
  bool colour_exposure_valid = false;
  // `texels` and `sh` as the renderer takes them, with the CPU half of its upload done
  // (render::prepare_levels): made here on the light thread, so that the processing thread's
  // frame at a new snapshot only uploads (issue #19's frame p99). Null in snapshots made
  // without a renderer in mind (none today).
  std::shared_ptr<const render::Environment> environment;
};

class LightCapture {
 public:
  // Throws std::invalid_argument when the rig's fisheye model is not one the update kernel
  // implements (Kannala-Brandt), or [light] room = "sim" and the rig knows no room; the
  // pipeline then runs without light capture and says so. The objects without a position
  // and [light] room = "auto" | "sim" take the rig's scene.
  // `poses`: the service's rig poses (the processing thread's, tracked and anchored); with
  // them the fisheye's pose is theirs at its timestamp and a frame without one is skipped
  // (keyframe updates pause while the pose is unknown). Without: the frames' truth, else
  // add_rig_pose()'s poses, else the origin (`eval render` drives the stage that way).
  LightCapture(const ServiceConfig& config, const RigCalibration& calibration,
               const RigScene& scene, std::shared_ptr<const PoseHistory> poses = {});
  ~LightCapture();
  LightCapture(const LightCapture&) = delete;
  LightCapture& operator=(const LightCapture&) = delete;

  // From the capture threads. A full queue drops the oldest frame (counted).
  void push(FisheyeFrame frame);
  void add_rig_pose(TimestampNs t, const Pose& T_world_rig);
  // From the RGB-D capture thread: the light thread copies a colour frame only when its
  // colour-exposure estimate is due (a few times per second), so this is cheap.
  void offer_rgbd(const RgbdFrame& frame);

  // The light thread's body: until stop is requested. Builds the OpenCL context first.
  // Beats `heartbeats`' "light" from its loop (at least every 100 ms while idle).
  void run(std::stop_token stop, StageStats& stats, HeartbeatRegistry& heartbeats);
  // run() in two steps, for a caller that drives the stage itself frame by frame (`eval
  // render` takes every sim frame in order, deterministically): initialise() builds the
  // OpenCL context and the estimators; process() takes one frame through the update, the
  // colour exposure and publishing. Both return false once the stage has failed (status()
  // says why); neither may run beside run().
  bool initialise();
  bool process(const FisheyeFrame& frame, StageStats* stats = nullptr);
  // Whether process() should take this frame at `[light] update_hz` (LightPacing); run()
  // asks for every frame, and a caller of process() should too. Counts the frames skipped.
  bool admit(const FisheyeFrame& frame);

  nlohmann::json status() const;
  // Radiance SH of the keyframe last updated, as of the last snapshot (publish() computes it).
  std::optional<ShRgb> latest_sh() const;
  // The newest snapshot; null until the first is published.
  std::shared_ptr<const LightSnapshot> latest_light() const;

 private:
  // T_world_rig at t: the frame's truth when it has one, else the RGB-D poses interpolated.
  std::optional<Pose> rig_pose_at(TimestampNs t,
                                  const std::shared_ptr<const FrameTruth>& truth) const;
  void fail(const std::string& what);
  void update_colour_exposure(const FisheyeFrame& frame);
  // Returns whether a snapshot was published (every kPublishIntervalNs of frame time).
  bool publish(const FisheyeFrame& frame);
  int fill_from_other_keyframes(envmap::ImageRGBAF& texels, const envmap::Keyframe& nearest);

  ServiceConfig config_;
  RigCalibration calibration_;
  struct Estimator;
  std::unique_ptr<Estimator> estimator_;

  mutable std::mutex mutex_;
  std::condition_variable_any arrived_;
  std::deque<FisheyeFrame> queue_;
  std::deque<std::pair<TimestampNs, Pose>> poses_;  // the last few seconds of RGB-D poses
  std::shared_ptr<const PoseHistory> service_poses_;
  std::uint64_t processed_ = 0, dropped_ = 0, without_pose_ = 0, paused_ = 0, skipped_ = 0;
  LightPacing pacing_;  // the light thread's (or process()'s caller's) only
  int keyframes_ = 0, active_keyframe_ = -1;
  std::uint64_t keyframes_dropped_ = 0;  // for [light] max_keyframes
  // /status: the keyframes kept (id, position) and the reprojection cache's entries, so that
  // a drift of the rig's poses and a cache outliving its keyframe both show from outside.
  std::vector<std::pair<int, Eigen::Vector3d>> kept_;
  std::size_t reprojected_count_ = 0;
  std::optional<ShRgb> sh_;
  std::shared_ptr<const LightSnapshot> snapshot_;
  std::uint64_t snapshot_version_ = 0;
  TimestampNs last_publish_ns_ = 0;
  std::vector<std::vector<float>> environment_scratch_;    // prepare_levels' chain, kept
  Eigen::Vector3d anchor_ = Eigen::Vector3d::Zero();       // the objects' mean position
  Eigen::Vector3d light_point_ = Eigen::Vector3d::Zero();  // 10 cm above it
  std::optional<envmap::RoomBox> room_;                    // [light] room
  // Per keyframe id (envmap::Keyframe::id: stable, never reused), where its texels land at the
  // light point (keyframes and the light point do not move, so it is built once) and, for the
  // keyframes other than the nearest, their reprojected texels with the update count they were made
  // at: only the active keyframe changes, so the others are reprojected again only after the rig
  // was near them.
  struct Reprojected {
    std::optional<envmap::ReprojectionMap> map;
    std::uint64_t updates = 0;
    envmap::ImageRGBAF texels;
  };
  std::map<int, Reprojected> reprojected_;
  Reprojected& reprojected(const envmap::Keyframe& keyframe);  // with its map built
  void forget_dropped_keyframes();  // the entries of keyframes the set no longer holds
  int keyframe_filled_texels_ = 0;
  bool want_rgbd_ = true;
  std::shared_ptr<const RgbdFrame> rgbd_;  // the copy offer_rgbd took
  // The colour frame the exposure was last estimated on: what fills the snapshot below the
  // fisheye's horizon ([light] colour_fill; kernels/light/colour_fill.hpp).
  std::shared_ptr<const RgbdFrame> fill_rgbd_;
  int colour_filled_texels_ = 0;
  TimestampNs last_colour_exposure_ns_ = 0;
  std::string state_ = "starting", error_, colour_error_;
};

}  // namespace probeless
