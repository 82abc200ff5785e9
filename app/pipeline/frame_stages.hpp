#pragma once
// The per-frame stages of the processing thread. Each is a small class with the same
// lifecycle (constructed from config on the processing thread, process() once per frame);
// FrameWork is the blackboard they pass along. Device images stay on the device between
// upload and download.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/pipeline/light_capture.hpp"
#include "app/render/renderer.hpp"
#include "core/calibration.hpp"
#include "core/frame.hpp"
#include "kernels/composite/compositor.hpp"
#include "kernels/composite/hdr_compositor.hpp"
#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless {

struct FrameWork {
  const RgbdFrame* input = nullptr;
  Pose T_world_camera;
  render::RenderTarget virtual_view;  // host: RGBA8 colour or float radiance, + depth in mm
  // The virtual layer is in radiance (the light capture's units), composited in HDR with the
  // colour camera's response; false: display colour under the placeholder light.
  bool hdr = false;
  CameraResponse camera;
  DeviceImageRGB8 color;
  DeviceDepthImage real_depth;
  DeviceImageRGBA8 virtual_color;
  DeviceImage<float, 4> virtual_radiance;
  DeviceImageF virtual_depth;
  DeviceImageF alpha;
  DeviceImageRGB8 composite;
  // Results on the host, handed to the outputs.
  std::shared_ptr<ImageRGB8> composite_host;
  std::shared_ptr<ImageF> alpha_host;  // only when an output wants the matte
  bool want_alpha = false;
};

class FrameStage {
 public:
  virtual ~FrameStage() = default;
  virtual const char* name() const = 0;  // the key in /status "stages"
  virtual void process(FrameWork& work) = 0;
};

// Where the render stage gets the captured light; null or returning null: no light yet.
using LightSource = std::function<std::shared_ptr<const LightSnapshot>()>;

// Renders the virtual objects at the colour camera's pose and intrinsics. With a light
// snapshot whose colour exposure is known, the image-based materials are lit by its keyframe
// and the layer is radiance for the HDR compositor; before that, the placeholder objects.
class RenderStage final : public FrameStage {
 public:
  RenderStage(std::vector<render::VirtualObject> objects, PinholeIntrinsics intrinsics,
              LightSource light = {});
  const char* name() const override { return "render"; }
  void process(FrameWork& work) override;

 private:
  render::Renderer renderer_;
  std::vector<render::VirtualObject> objects_;
  std::vector<render::VirtualObject> placeholders_;
  PinholeIntrinsics intrinsics_;
  LightSource light_;
  std::uint64_t light_version_ = 0;
  bool image_based_ = false;
};

// Host -> device: the real frame and the rendered virtual view.
class UploadStage final : public FrameStage {
 public:
  explicit UploadStage(ComputeContext& ctx) : ctx_(ctx) {}
  const char* name() const override { return "upload"; }
  void process(FrameWork& work) override;

 private:
  ComputeContext& ctx_;
};

class OcclusionStage final : public FrameStage {
 public:
  explicit OcclusionStage(std::unique_ptr<occlusion::OcclusionMethod> method)
      : method_(std::move(method)) {}
  const char* name() const override { return "occlusion"; }
  void process(FrameWork& work) override;
  std::string method_name() const { return method_->name(); }

 private:
  std::unique_ptr<occlusion::OcclusionMethod> method_;
};

class CompositeStage final : public FrameStage {
 public:
  explicit CompositeStage(ComputeContext& ctx) : ctx_(ctx), composite_(ctx), hdr_(ctx) {}
  const char* name() const override { return "composite"; }
  void process(FrameWork& work) override;

 private:
  ComputeContext& ctx_;
  Compositor composite_;
  HdrCompositor hdr_;
};

// Device -> host, waiting for the queue: the end of the device work of the frame.
class DownloadStage final : public FrameStage {
 public:
  explicit DownloadStage(ComputeContext& ctx) : ctx_(ctx) {}
  const char* name() const override { return "download"; }
  void process(FrameWork& work) override;

 private:
  ComputeContext& ctx_;
};

}  // namespace probeless
