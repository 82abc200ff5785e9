#pragma once
// The occlusion stage: every matte method (Direct1/2, CVF, Guided, Bilateral, Crabb, ...) is a
// class behind this interface, chosen by name in config (ServiceConfig::occlusion_method).
// Inputs and output stay on the device; a method enqueues its work on the queue of the
// ComputeContext it was constructed with and does not wait for it (the in-order queue orders
// the next stage after it; whoever downloads the result waits).
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/pixel_rect.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::occlusion {

// All on the device, all the same width x height (the RGB-D camera's colour frame, with the
// real depth registered to it and the virtual depth rendered from the same camera).
struct OcclusionInputs {
  OcclusionInputs() = default;
  OcclusionInputs(const DeviceImage<std::uint8_t, 3>* colour_rgb,
                  const DeviceImage<std::uint16_t, 1>* real_mm,
                  const DeviceImage<float, 1>* virtual_mm,
                  std::optional<PixelRect> object_pixels = std::nullopt)
      : colour(colour_rgb),
        real_depth_mm(real_mm),
        virtual_depth_mm(virtual_mm),
        objects(object_pixels) {}

  const DeviceImage<std::uint8_t, 3>* colour = nullptr;          // real RGB8 frame (the guide)
  const DeviceImage<std::uint16_t, 1>* real_depth_mm = nullptr;  // 0 = unknown
  const DeviceImage<float, 1>* virtual_depth_mm = nullptr;       // 0 = no virtual object there
  // Where the virtual depth may be > 0: it is 0 everywhere else (the renderer's drawn
  // rectangle, RenderTarget::drawn). None: anywhere. Stages that are given it compute only
  // there and within their reach around it, with the same result as over the whole frame.
  std::optional<PixelRect> objects;

  int width() const { return colour ? colour->width() : 0; }
  int height() const { return colour ? colour->height() : 0; }
  // `objects` clipped to the frame; the whole frame without it.
  PixelRect object_rect() const {
    const auto whole = PixelRect::whole(width(), height());
    return objects ? intersect(*objects, whole) : whole;
  }
};

// Throws std::invalid_argument unless every input is present and they all share one size.
// Methods call it at the top of process().
inline void check_inputs(const OcclusionInputs& in, const std::string& method) {
  if (!in.colour || !in.real_depth_mm || !in.virtual_depth_mm)
    throw std::invalid_argument(method + ": an occlusion input is missing");
  if (!in.real_depth_mm->same_size(*in.colour) || !in.virtual_depth_mm->same_size(*in.colour))
    throw std::invalid_argument(method + ": occlusion inputs differ in size");
}

class OcclusionMethod {
 public:
  virtual ~OcclusionMethod() = default;
  // The config name: "direct1", "direct2", "cvf", ...
  virtual std::string name() const = 0;
  // alpha = visibility of the virtual object in [0, 1] (1 = the virtual object is in front),
  // 0 wherever there is no virtual object. `alpha` is resized to the inputs when it differs
  // (so a default-constructed DeviceImage works), then written on every pixel.
  virtual void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) = 0;
  // The real depth as the last process() understood it, where the method changed the sensor's
  // (CVF's near occluders: a wide hole is a surface nearer than the sensor's minimum range,
  // marked over its whole extent, hole_core_reference.hpp); nullptr = the input's. Stages
  // after it that compare depths (the temporal stabiliser) take this one, so that they see the
  // occluder the matte saw. Enqueues its work when first asked after a process(); valid until
  // the next process().
  virtual const DeviceImage<std::uint16_t, 1>* judged_depth() { return nullptr; }

  // `in` with the depth the last process() judged by.
  OcclusionInputs as_judged(const OcclusionInputs& in) {
    OcclusionInputs out = in;
    if (const auto* d = judged_depth()) out.real_depth_mm = d;
    return out;
  }
};

}  // namespace probeless::occlusion
