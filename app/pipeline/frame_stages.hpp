#pragma once
// The per-frame stages of the processing thread. Each is a small class constructed from
// config on the processing thread, with one typed call per frame: what it takes is what the
// stage before it returned, so no stage reads a flag another one left behind.
//
//   render(pose)                    -> VirtualLayer  (host: LDR colour or HDR radiance, depth)
//   upload(frame, layer)            -> DeviceFrame   (the real and the virtual images)
//   occlusion(device frame)         -> the matte
//   composite(device frame, matte)  -> the device composite
//   download(composite, matte)      -> PendingDownload (reads enqueued), then wait() -> HostImages
//
// Each stage owns the images it returns and reuses them frame after frame; what it returns
// refers to them and is valid until its next call. Device images stay on the device between
// upload and download. Two frames may be on the way at once (FrameProcessor::submit): one
// whose device work runs while the next is rendered and uploaded. What the device reads from
// host memory therefore comes in kFrameSlots copies, picked by the caller's `slot` (render
// target, the wrapped virtual layer, the judged depth); device-only images need one copy, as
// the queue is in order: frame N+1's writes to them run after frame N's reads.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "app/pipeline/image_pool.hpp"
#include "app/pipeline/light_capture.hpp"
#include "app/render/renderer.hpp"
#include "core/beyond_range.hpp"
#include "core/calibration.hpp"
#include "core/frame.hpp"
#include "kernels/composite/compositor.hpp"
#include "kernels/composite/hdr_compositor.hpp"
#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/occlusion/foreground/foreground_estimate.hpp"
#include "kernels/occlusion/temporal/matte_stabiliser.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"
#include "kernels/undistort/undistort.hpp"

namespace probeless {

// The virtual objects' colour: display colour under the placeholder light (before any light
// is captured), or radiance in the light capture's units, composited in HDR with the colour
// camera's response.
struct LdrColour {
  const ImageRGBA8* colour = nullptr;
};
struct HdrRadiance {
  const render::ImageRGBAF* radiance = nullptr;
  CameraResponse camera;
};

// The render stage's result, on the host.
struct VirtualLayer {
  std::variant<LdrColour, HdrRadiance> colour;
  const ImageF* depth_mm = nullptr;  // along the optical axis; 0 where no object
  // Where the layer may be non-zero (RenderTarget::drawn): it is all zeros outside. None:
  // anywhere.
  std::optional<PixelRect> drawn;
};

// Frames whose host memory the device may be reading at once: the one in flight and the one
// being submitted (FrameProcessor).
inline constexpr int kFrameSlots = 2;

// The upload stage's result: the real frame and the virtual layer on the device.
struct DeviceLdrColour {
  const DeviceImageRGBA8* colour = nullptr;
};
struct DeviceHdrRadiance {
  const DeviceImage<float, 4>* radiance = nullptr;
  CameraResponse camera;
};
struct DeviceFrame {
  const DeviceImageRGB8* colour = nullptr;
  const DeviceDepthImage* real_depth = nullptr;
  std::variant<DeviceLdrColour, DeviceHdrRadiance> virtual_colour;
  const DeviceImageF* virtual_depth = nullptr;
  // VirtualLayer::drawn: the stages after the upload compute only there and around it
  // (OcclusionInputs::objects).
  std::optional<PixelRect> objects;
};

// The download stage's result, handed to the outputs.
struct HostImages {
  std::shared_ptr<ImageRGB8> composite;
  std::shared_ptr<ImageF> matte;  // only when an output wants it
};

// The download enqueued: `images` fill in on the device's time, complete once `done` has.
struct PendingDownload {
  HostImages images;
  ::cl::Event done;  // a marker after the reads, so after every command of the frame
};

// Where the render stage gets the captured light; null or returning null: no light yet.
using LightSource = std::function<std::shared_ptr<const LightSnapshot>()>;

// Renders the virtual objects at the colour camera's pose and intrinsics. With a light
// snapshot whose colour exposure is known, the image-based materials are lit by its keyframe
// and the layer is radiance for the HDR compositor; before that, the placeholder objects.
class RenderStage {
 public:
  RenderStage(std::vector<render::VirtualObject> objects, PinholeIntrinsics intrinsics,
              LightSource light = {});
  static constexpr const char* name = "render";  // the key in /status "stages", as below
  // Draws into target `slot` (0 .. kFrameSlots-1): the layer is valid until the next call
  // with the same slot, so the device may read the other slot's layer meanwhile.
  VirtualLayer process(const Pose& T_world_camera, int slot = 0);

 private:
  render::Renderer renderer_;
  std::vector<render::VirtualObject> objects_;
  std::vector<render::VirtualObject> placeholders_;
  PinholeIntrinsics intrinsics_;
  LightSource light_;
  std::uint64_t light_version_ = 0;
  bool image_based_ = false;
  // Host: RGBA8 colour or float radiance, + depth in mm. One per slot: 6.1 MB each with the
  // HDR layer, which the device reads in place (UploadStage) until its frame's download.
  render::RenderTarget views_[kFrameSlots];
};

// Host -> device: the real frame and the rendered virtual layer. The renderer draws with the
// colour camera's pinhole without distortion; with Brown distortion in the calibration the
// colour (bilinear) and the depth registered to it (nearest) are remapped on the device to
// that pinhole (kernels/undistort), so the matte, the composite and the renderer agree pixel
// for pixel. Without distortion nothing is remapped: the upload is the copy it always was.
class UploadStage {
 public:
  // `beyond_range`: the holes it finds are filled before the upload (core/beyond_range.hpp),
  // so every occlusion stage sees them far; tracking reads the frame's own depth.
  UploadStage(ComputeContext& ctx, const PinholeCamera& rgb, BeyondRangeRule beyond_range = {});
  static constexpr const char* name = "upload";
  // Non-blocking writes: `frame` and `layer`'s images must live until the download. `slot`
  // (0 .. kFrameSlots-1) holds what the device reads from host memory besides them: the
  // wrapped layer and the judged depth, kept until the next call with the same slot. A frame
  // whose colour or depth is not the calibration's colour camera size is an
  // std::invalid_argument naming both.
  DeviceFrame process(const RgbdFrame& frame, const VirtualLayer& layer, int slot = 0);
  // The same size check alone, for stages that run before the upload (tracking).
  void check_size(const RgbdFrame& frame) const;
  bool undistorts() const { return undistort_.has_value(); }

 private:
  ComputeContext& ctx_;
  int width_, height_;  // the calibration's colour camera
  std::optional<Undistort> undistort_;
  BeyondRangeRule beyond_range_;
  BeyondRangeScratch beyond_range_scratch_;
  DeviceImageRGB8 raw_colour_;  // as the camera delivered it, when undistorting
  DeviceDepthImage raw_depth_;
  DeviceImageRGB8 colour_;
  DeviceDepthImage real_depth_;
  // What the device reads from host memory, per slot (see process()).
  struct Slot {
    DepthImage judged_depth;  // the frame's depth with the beyond-range holes filled
    DeviceImageRGBA8 virtual_colour;
    DeviceImage<float, 4> virtual_radiance;
    DeviceImageF virtual_depth;
  };
  Slot slots_[kFrameSlots];
};

class OcclusionStage {
 public:
  // With `stabilise`, the method's matte is then stabilised in time (kernels/occlusion/
  // temporal: the previous matte re-projected with the camera's motion and the depth).
  OcclusionStage(ComputeContext& ctx, std::unique_ptr<occlusion::OcclusionMethod> method,
                 bool stabilise = false, const PinholeIntrinsics& intrinsics = {});
  static constexpr const char* name = "occlusion";
  // The matte: alpha of the virtual layer per pixel, the colour image's size.
  // `T_world_camera`: the colour camera's pose this frame (the tracked one); none: the
  // stabiliser takes the camera as not having moved.
  const DeviceImageF& process(const DeviceFrame& frame,
                              const std::optional<Pose>& T_world_camera = std::nullopt);
  // A frame without a matte (pose lost): the next matte does not lean on an older one.
  void skip_frame() {
    if (stabiliser_) stabiliser_->reset();
  }
  std::string method_name() const { return method_->name(); }
  bool stabilises() const { return stabiliser_.has_value(); }

 private:
  ComputeContext& ctx_;
  std::unique_ptr<occlusion::OcclusionMethod> method_;
  std::optional<occlusion::MatteStabiliser> stabiliser_;
  PinholeIntrinsics intrinsics_;
  DeviceImageF alpha_;
};

// Composites with the estimated real foreground colour where the matte is fractional
// (docs/compositing.md "Foreground colour at soft edges"), not the observed mix that still
// holds the background the virtual object replaces.
class CompositeStage {
 public:
  explicit CompositeStage(ComputeContext& ctx)
      : ctx_(ctx), foreground_(ctx), composite_(ctx), hdr_(ctx) {}
  static constexpr const char* name = "composite";
  const DeviceImageRGB8& process(const DeviceFrame& frame, const DeviceImageF& matte);

 private:
  ComputeContext& ctx_;
  occlusion::ForegroundEstimate foreground_;
  DeviceImageRGB8 real_;  // the colour frame with F at fractional matte pixels
  Compositor composite_;
  HdrCompositor hdr_;
  DeviceImageRGB8 out_;
};

// Device -> host: the end of the device work of the frame. process() enqueues the reads into
// host images no output holds (ImagePool) without waiting and flushes, so the device starts on the
// frame while the host goes on (FrameProcessor::submit); wait() is the wait, timed as this stage.
class DownloadStage {
 public:
  DownloadStage(ComputeContext& ctx, bool want_matte) : ctx_(ctx), want_matte_(want_matte) {}
  // Images handed out and not yet let go by every output are never written again; the pools
  // keep up to kPooledImages each (two frames on the way, the output slot, the encoders' and
  // the last good frame's, with room to spare) and allocate beyond that.
  static constexpr std::size_t kPooledImages = 8;
  static constexpr const char* name = "download";
  PendingDownload process(const DeviceImageRGB8& composite, const DeviceImageF& matte);
  // Until `pending.done`; its images are then complete.
  static HostImages wait(PendingDownload& pending);

 private:
  ComputeContext& ctx_;
  bool want_matte_;
  ImagePool<std::uint8_t, 3> composites_{kPooledImages};
  ImagePool<float, 1> mattes_{kPooledImages};
};

}  // namespace probeless
