#include "app/pipeline/frame_processor.hpp"

#include <chrono>

#include "app/pipeline/scene_objects.hpp"
#include "kernels/occlusion/method_registry.hpp"

namespace probeless {

FrameProcessor::FrameProcessor(const ServiceConfig& config, const RigCalibration& calibration,
                               bool keep_matte, LightSource light)
    : calibration_(calibration), keep_matte_(keep_matte) {
  ComputeOptions options;
  if (!config.cl_platform.empty()) options.selector.platform_substring = config.cl_platform;
  if (!config.cl_device.empty()) options.selector.device_substring = config.cl_device;
  ctx_ = std::make_unique<ComputeContext>(options);

  stages_.push_back(std::make_unique<RenderStage>(
      make_scene_objects(config.objects, config.ground, default_prt_cache_dir()),
      calibration.rgb.intrinsics(), std::move(light)));
  stages_.push_back(std::make_unique<UploadStage>(*ctx_));
  auto occlusion =
      std::make_unique<OcclusionStage>(occlusion::make_method(*ctx_, config.occlusion_method));
  occlusion_ = occlusion.get();
  stages_.push_back(std::move(occlusion));
  stages_.push_back(std::make_unique<CompositeStage>(*ctx_));
  stages_.push_back(std::make_unique<DownloadStage>(*ctx_));
  work_.want_alpha = keep_matte;
}

CompositeFrame FrameProcessor::process(const RgbdFrame& frame, StageStats& stats) {
  // The rig pose comes with the frame when the source knows it (the synthetic rig, a
  // recording with a trajectory); camera tracking is not part of probeless yet, so a source
  // without poses keeps the last one (identity at first): a static rig.
  if (frame.truth && frame.truth->rig_pose) last_rig_pose_ = *frame.truth->rig_pose;
  work_.input = &frame;
  work_.T_world_camera = last_rig_pose_ * calibration_.T_rig_rgb;

  const auto frame_start = std::chrono::steady_clock::now();
  for (auto& stage : stages_) {
    const auto t0 = std::chrono::steady_clock::now();
    stage->process(work_);
    stats.record(
        stage->name(),
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  stats.record("frame", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                                  frame_start)
                            .count());

  CompositeFrame out;
  out.sequence = frame.sequence;
  out.timestamp_ns = frame.timestamp_ns;
  out.color = work_.composite_host;
  out.alpha = work_.alpha_host;
  if (keep_matte_) out.virtual_depth = std::make_shared<const ImageF>(work_.virtual_view.depth_mm);
  out.truth = frame.truth;
  work_.input = nullptr;
  return out;
}

}  // namespace probeless
