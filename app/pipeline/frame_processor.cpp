#include "app/pipeline/frame_processor.hpp"

#include <chrono>

#include "app/pipeline/scene_objects.hpp"
#include "kernels/occlusion/method_registry.hpp"

namespace probeless {

namespace {

std::unique_ptr<ComputeContext> make_context(const ServiceConfig& config) {
  ComputeOptions options;
  if (!config.cl_platform.empty()) options.selector.platform_substring = config.cl_platform;
  if (!config.cl_device.empty()) options.selector.device_substring = config.cl_device;
  return std::make_unique<ComputeContext>(options);
}

// Runs one stage, its time recorded under its name.
template <typename Stage, typename... Args>
decltype(auto) timed(StageStats& stats, Stage& stage, Args&&... args) {
  const auto t0 = std::chrono::steady_clock::now();
  decltype(auto) result = stage.process(std::forward<Args>(args)...);
  stats.record(Stage::name, ms_since(t0));
  return result;
}

}  // namespace

FrameProcessor::FrameProcessor(const ServiceConfig& config, const RigCalibration& calibration,
                               bool keep_matte, LightSource light)
    : calibration_(calibration),
      keep_matte_(keep_matte),
      ctx_(make_context(config)),
      render_(make_scene_objects(config.objects, config.ground, default_prt_cache_dir()),
              calibration.rgb.intrinsics(), std::move(light)),
      upload_(*ctx_, calibration.rgb),
      occlusion_(*ctx_, occlusion::make_method(*ctx_, config.occlusion_method)),
      composite_(*ctx_),
      download_(*ctx_, keep_matte) {}

CompositeFrame FrameProcessor::process(const RgbdFrame& frame, StageStats& stats) {
  // The rig pose comes with the frame when the source knows it (the synthetic rig, a
  // recording with a trajectory); camera tracking is not part of probeless yet, so a source
  // without poses keeps the last one (identity at first): a static rig.
  if (frame.truth && frame.truth->rig_pose) last_rig_pose_ = *frame.truth->rig_pose;
  const Pose T_world_camera = last_rig_pose_ * calibration_.T_rig_rgb;

  const auto frame_start = std::chrono::steady_clock::now();
  const VirtualLayer layer = timed(stats, render_, T_world_camera);
  const DeviceFrame device = timed(stats, upload_, frame, layer);
  const DeviceImageF& matte = timed(stats, occlusion_, device);
  const DeviceImageRGB8& composite = timed(stats, composite_, device, matte);
  HostImages host = timed(stats, download_, composite, matte);
  stats.record("frame", ms_since(frame_start));

  CompositeFrame out;
  out.sequence = frame.sequence;
  out.timestamp_ns = frame.timestamp_ns;
  out.colour = std::move(host.composite);
  out.alpha = std::move(host.matte);
  if (keep_matte_) out.virtual_depth = std::make_shared<const ImageF>(*layer.depth_mm);
  out.truth = frame.truth;
  return out;
}

}  // namespace probeless
