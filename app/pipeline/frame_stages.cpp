#include "app/pipeline/frame_stages.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "app/pipeline/scene_objects.hpp"

namespace probeless {

RenderStage::RenderStage(std::vector<render::VirtualObject> objects, PinholeIntrinsics intrinsics,
                         LightSource light)
    : renderer_(renderer_config_for(objects)),
      objects_(std::move(objects)),
      placeholders_(placeholder_objects(objects_)),
      intrinsics_(intrinsics),
      light_(std::move(light)) {
  for (const auto& o : objects_)
    image_based_ = image_based_ || o.material.shading != render::Material::Shading::Lambert;
}

namespace {

int checked_slot(int slot) {
  if (slot < 0 || slot >= kFrameSlots)
    throw std::out_of_range(fmt::format("frame slot {} (0 .. {})", slot, kFrameSlots - 1));
  return slot;
}

}  // namespace

VirtualLayer RenderStage::process(const Pose& T_world_camera, int slot) {
  render::RenderTarget& view = views_[checked_slot(slot)];
  const std::shared_ptr<const LightSnapshot> snap =
      image_based_ && light_ ? light_() : std::shared_ptr<const LightSnapshot>{};
  if (!(snap && snap->colour_exposure_valid)) {
    view.output = render::ColourOutput::Display8;
    renderer_.render({intrinsics_, T_world_camera}, placeholders_, view);
    return {LdrColour{&view.colour}, &view.depth_mm, view.drawn};
  }
  if (snap->version != light_version_) {
    // A new keyframe copy: a new Environment, uploaded and prefiltered once for all objects.
    // The light thread made it, with the CPU half of the upload (LightSnapshot::environment).
    auto env = snap->environment ? snap->environment
                                 : std::make_shared<const render::Environment>(
                                       render::make_environment(snap->texels, snap->sh));
    renderer_.prepare(env);
    for (auto& o : objects_) o.environment = env;
    light_version_ = snap->version;
  }
  HdrRadiance hdr{&view.radiance, {}};
  for (int c = 0; c < 3; ++c) hdr.camera.exposure[c] = snap->colour_exposure[c];
  view.output = render::ColourOutput::LinearFloat;
  renderer_.render({intrinsics_, T_world_camera}, objects_, view);
  return {hdr, &view.depth_mm, view.drawn};
}

UploadStage::UploadStage(ComputeContext& ctx, const PinholeCamera& rgb,
                         BeyondRangeRule beyond_range)
    : ctx_(ctx), width_(rgb.width()), height_(rgb.height()), beyond_range_(beyond_range) {
  if (const auto map = build_undistort_map(rgb)) undistort_.emplace(ctx, *map);
}

namespace {

// A source at another resolution than the calibration would be drawn over at the wrong
// pixels without a sign of it: say which two sizes disagree.
void check_size(const char* what, int w, int h, int want_w, int want_h) {
  if (w != want_w || h != want_h)
    throw std::invalid_argument(fmt::format(
        "the source's {} frames are {} x {}, but the calibration's colour camera is {} x {} "
        "(calibrate at the size the source runs at, or set its size= to the calibration's)",
        what, w, h, want_w, want_h));
}

}  // namespace

void UploadStage::check_size(const RgbdFrame& frame) const {
  probeless::check_size("colour", frame.colour.width(), frame.colour.height(), width_, height_);
  probeless::check_size("depth", frame.depth.width(), frame.depth.height(), width_, height_);
}

DeviceFrame UploadStage::process(const RgbdFrame& frame, const VirtualLayer& layer, int slot) {
  auto& q = ctx_.queue();
  check_size(frame);
  Slot& s = slots_[checked_slot(slot)];
  const DepthImage* depth = &frame.depth;
  if (measures_beyond_range(frame.depth, beyond_range_)) {
    // Kept until the slot's next frame: the upload below does not block. Only when something
    // is that far: the copy was the processing thread's largest memmove in `perf`.
    s.judged_depth = frame.depth;
    fill_beyond_range_holes(s.judged_depth, beyond_range_, beyond_range_scratch_);
    depth = &s.judged_depth;
  }
  if (undistort_) {
    raw_colour_.upload(q, frame.colour, false);
    raw_depth_.upload(q, *depth, false);
    undistort_->colour(raw_colour_, colour_);
    undistort_->depth(raw_depth_, real_depth_);
  } else {
    colour_.upload(q, frame.colour, false);
    real_depth_.upload(q, *depth, false);
  }
  DeviceFrame out{&colour_, &real_depth_, {}, &s.virtual_depth, layer.drawn};
  // The virtual layer is read in place (CL_MEM_USE_HOST_PTR; no copy on PoCL and on boards
  // whose GPU shares the memory): the render stage keeps it in the same slot until that
  // slot's next render, after this frame's download has been waited for. 6.1 MB a frame with
  // the HDR layer (radiance float4 + depth), the PoCL workers' largest memcpy in `perf`
  // (docs/performance.md).
  const auto& c = ctx_.context();
  if (const auto* hdr = std::get_if<HdrRadiance>(&layer.colour)) {
    s.virtual_radiance = DeviceImage<float, 4>::wrap_host(c, *hdr->radiance);
    out.virtual_colour = DeviceHdrRadiance{&s.virtual_radiance, hdr->camera};
  } else {
    s.virtual_colour = DeviceImageRGBA8::wrap_host(c, *std::get<LdrColour>(layer.colour).colour);
    out.virtual_colour = DeviceLdrColour{&s.virtual_colour};
  }
  s.virtual_depth = DeviceImageF::wrap_host(c, *layer.depth_mm);
  return out;
}

OcclusionStage::OcclusionStage(ComputeContext& ctx,
                               std::unique_ptr<occlusion::OcclusionMethod> method, bool stabilise,
                               const PinholeIntrinsics& intrinsics)
    : ctx_(ctx), method_(std::move(method)), intrinsics_(intrinsics) {
  if (stabilise) stabiliser_.emplace(ctx);
}

const DeviceImageF& OcclusionStage::process(const DeviceFrame& frame,
                                            const std::optional<Pose>& T_world_camera) {
  alpha_.resize(ctx_.context(), frame.colour->width(), frame.colour->height());
  const occlusion::OcclusionInputs in{frame.colour, frame.real_depth, frame.virtual_depth,
                                      frame.objects};
  method_->process(in, alpha_);
  if (stabiliser_)
    stabiliser_->process(method_->as_judged(in), intrinsics_, T_world_camera, alpha_);
  return alpha_;
}

const DeviceImageRGB8& CompositeStage::process(const DeviceFrame& frame,
                                               const DeviceImageF& matte) {
  out_.resize(ctx_.context(), frame.colour->width(), frame.colour->height());
  // Both work only over the objects' rectangle (the matte is 0 outside it) after a copy of
  // the frame: the copies are memcpys, the kernels were 9 % of the bench's CPU samples.
  foreground_.process(*frame.colour, *frame.virtual_depth, matte, real_, frame.objects);
  if (const auto* hdr = std::get_if<DeviceHdrRadiance>(&frame.virtual_colour))
    hdr_.process(real_, *hdr->radiance, matte, hdr->camera, out_, frame.objects);
  else
    composite_.process(real_, *std::get<DeviceLdrColour>(frame.virtual_colour).colour, matte, out_);
  return out_;
}

namespace {

// A read that does not wait: `host` (already the device image's size) must stay where it is
// until an event after it has completed.
template <typename T, int C>
void enqueue_read(::cl::CommandQueue& q, const DeviceImage<T, C>& device, Image<T, C>& host) {
  if (!device.empty())
    q.enqueueReadBuffer(device.buffer(), CL_FALSE, 0, device.size_bytes(), host.data());
}

}  // namespace

PendingDownload DownloadStage::process(const DeviceImageRGB8& composite,
                                       const DeviceImageF& matte) {
  auto& q = ctx_.queue();
  // Images no output holds any more (image_pool.hpp): the outputs keep theirs through
  // shared_ptr while the next frames are processed, and the device writes into these while the
  // next frame is rendered.
  PendingDownload out;
  out.images.composite = composites_.take(composite.width(), composite.height());
  enqueue_read(q, composite, *out.images.composite);
  if (want_matte_) {
    out.images.matte = mattes_.take(matte.width(), matte.height());
    enqueue_read(q, matte, *out.images.matte);
  }
  // One event for the whole frame: the queue is in order, so the marker completes after every
  // command before it. The flush hands the frame to PoCL's workers now rather than at the
  // next blocking call, which would be the next frame's.
  q.enqueueMarkerWithWaitList(nullptr, &out.done);
  q.flush();
  return out;
}

HostImages DownloadStage::wait(PendingDownload& pending) {
  pending.done.wait();
  return std::move(pending.images);
}

}  // namespace probeless
