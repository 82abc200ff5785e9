#pragma once
// The processing thread's work for one RGB-D frame: the stages of frame_stages.hpp composed
// from config, each one's result the next one's input, each timed into StageStats. Owns the
// OpenCL context and the EGL renderer, so it must be created, used and destroyed on one
// thread.
#include <memory>
#include <string>

#include "app/pipeline/frame_stages.hpp"
#include "app/pipeline/pipeline.hpp"
#include "app/pipeline/service_config.hpp"
#include "base/stage_stats.hpp"

namespace probeless {

class FrameProcessor {
 public:
  // `light`: the light capture's snapshots (LightCapture::latest_light), if it runs.
  FrameProcessor(const ServiceConfig& config, const RigCalibration& calibration, bool keep_matte,
                 LightSource light = {});
  CompositeFrame process(const RgbdFrame& frame, StageStats& stats);

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
  Pose last_rig_pose_;
};

}  // namespace probeless
