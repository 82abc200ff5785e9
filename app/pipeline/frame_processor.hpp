#pragma once
// The processing thread's work for one RGB-D frame: the stages of frame_stages.hpp composed
// from config, each one's result the next one's input, each timed into StageStats. Owns the
// OpenCL context and the EGL renderer, so it must be created, used and destroyed on one
// thread.
#include <memory>
#include <string>

#include "app/pipeline/frame_stages.hpp"
#include "app/pipeline/pipeline.hpp"
#include "app/pipeline/pose_history.hpp"
#include "app/pipeline/service_config.hpp"
#include "app/world/rig_localiser.hpp"
#include "base/stage_stats.hpp"

namespace probeless {

class FrameProcessor {
 public:
  // `light`: the light capture's snapshots (LightCapture::latest_light), if it runs.
  // `poses`: where each frame's rig pose (or its absence) goes for the light thread.
  FrameProcessor(const ServiceConfig& config, const RigCalibration& calibration, bool keep_matte,
                 LightSource light = {}, std::shared_ptr<PoseHistory> poses = {});
  CompositeFrame process(const RgbdFrame& frame, StageStats& stats);
  // Where the rig is, as of the last frame (/status "tracking").
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

  // The camera image alone with a small banner: what is shown while the pose is unknown.
  CompositeFrame camera_only(const RgbdFrame& frame) const;
};

}  // namespace probeless
