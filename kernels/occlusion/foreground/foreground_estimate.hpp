#pragma once
// The device stage of foreground_estimate_reference.hpp: the colour frame with the estimated
// real foreground colour in place of the observed mix at fractional matte pixels, for the
// compositor (docs/compositing.md "Foreground colour at soft edges").
#include <optional>

#include "core/pixel_rect.hpp"
#include "kernels/occlusion/foreground/foreground_estimate_reference.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::occlusion {

class ForegroundEstimate {
 public:
  // Throws std::invalid_argument for bad params (validate()).
  explicit ForegroundEstimate(ComputeContext& ctx, const ForegroundEstimateParams& params = {});

  // out (resized) = colour with F at fractional visibility on the object. Throws
  // std::invalid_argument when the sizes differ. Enqueues its work and does not wait.
  // `objects` (OcclusionInputs::objects): the virtual depth is 0 outside it, so no pixel
  // there is fractional; a copy of the colour and the kernel over the rectangle give the
  // same image as the kernel over the frame (6.2 % of `bench pipeline`'s CPU samples with
  // the whole frame, docs/performance.md).
  void process(const DeviceImageRGB8& colour, const DeviceImageF& virtual_depth_mm,
               const DeviceImageF& visibility, DeviceImageRGB8& out,
               const std::optional<PixelRect>& objects = std::nullopt);

 private:
  ComputeContext& ctx_;
  ForegroundEstimateParams params_;
  ::cl::Kernel kernel_;
  ::cl::Buffer decode_;
};

}  // namespace probeless::occlusion
