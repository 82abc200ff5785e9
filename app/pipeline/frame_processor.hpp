#pragma once
// The processing thread's work for one RGB-D frame: the stages of frame_stages.hpp composed
// from config, each one's result the next one's input, each timed into StageStats. Owns the
// OpenCL context and the EGL renderer, so it must be created, used and destroyed on one
// thread; only locate() may run on another (one call at a time) when tracking_apart() says
// so: the processing loop tracks the next frame there while this one is composed.
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "app/pipeline/frame_stages.hpp"
#include "app/pipeline/pipeline.hpp"
#include "app/pipeline/pose_history.hpp"
#include "app/pipeline/service_config.hpp"
#include "app/world/rig_localiser.hpp"
#include "base/stage_stats.hpp"
#include "kernels/occlusion/method_registry.hpp"

namespace probeless {

// The occlusion method's parameters from [occlusion] (its method's defaults otherwise).
occlusion::MethodParams occlusion_params(const ServiceConfig& config);
// The sensor's beyond-range holes from [occlusion] beyond_range_m (0 turns the rule off).
BeyondRangeRule beyond_range_rule(const ServiceConfig& config);

class FrameProcessor {
 public:
  // `light`: the light capture's snapshots (LightCapture::latest_light), if it runs.
  // `poses`: where each frame's rig pose (or its absence) goes for the light thread.
  FrameProcessor(const ServiceConfig& config, const RigCalibration& calibration, bool keep_matte,
                 LightSource light = {}, std::shared_ptr<PoseHistory> poses = {});
  // Where the rig is at one frame, and /status "tracking" as of that frame.
  struct Located {
    std::optional<Pose> T_world_rig;
    world::LocaliserStatus status;
    std::chrono::steady_clock::time_point started;  // when locate() began: the frame's start
  };

  // locate() then compose(): the frame on this thread alone.
  CompositeFrame process(const RgbdFrame& frame, StageStats& stats);
  // The tracking stage ("tracking"): the rig pose, also handed to the light thread (`poses`).
  // Frames in order, one call at a time.
  Located locate(const RgbdFrame& frame, StageStats& stats);
  // Everything after tracking: render, upload, matte, composite, download ("frame": from
  // located.started to the end).
  CompositeFrame compose(const RgbdFrame& frame, const Located& located, StageStats& stats);
  // Whether locate() may run on another thread beside compose(): the tracker does not use
  // this thread's OpenCL context (`[tracking] device = "cpu"`, the default, or no tracker).
  bool tracking_apart() const { return tracking_apart_; }
  // Where the rig is, as of the last frame located (/status "tracking").
  const world::LocaliserStatus& tracking() const { return localiser_.status(); }

  std::string occlusion_method() const { return occlusion_.method_name(); }
  std::string device_description() const { return ctx_->describe(); }

 private:
  RigCalibration calibration_;
  bool keep_matte_;
  std::unique_ptr<ComputeContext> ctx_;
  RenderStage render_;
  UploadStage upload_;
  OcclusionStage occlusion_;
  CompositeStage composite_;
  DownloadStage download_;
  world::RigLocaliser localiser_;
  std::shared_ptr<PoseHistory> poses_;
  bool tracking_apart_;

  // The camera image alone with a small banner: what is shown while the pose is unknown.
  CompositeFrame camera_only(const RgbdFrame& frame, const world::LocaliserStatus& s) const;
};

}  // namespace probeless
