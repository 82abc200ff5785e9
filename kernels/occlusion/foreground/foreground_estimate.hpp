#pragma once
// The device stage of foreground_estimate_reference.hpp: the colour frame with the estimated
// real foreground colour in place of the observed mix at fractional matte pixels, for the
// compositor (docs/compositing.md "Foreground colour at soft edges").
#include "kernels/occlusion/foreground/foreground_estimate_reference.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::occlusion {

class ForegroundEstimate {
 public:
  // Throws std::invalid_argument for bad params (validate()).
  explicit ForegroundEstimate(ComputeContext& ctx, const ForegroundEstimateParams& params = {});

  // out (resized) = colour with F at fractional visibility on the object. Throws
  // std::invalid_argument when the sizes differ. Enqueues one kernel and does not wait.
  void process(const DeviceImageRGB8& colour, const DeviceImageF& virtual_depth_mm,
               const DeviceImageF& visibility, DeviceImageRGB8& out);

 private:
  ComputeContext& ctx_;
  ForegroundEstimateParams params_;
  ::cl::Kernel kernel_;
  ::cl::Buffer decode_;
};

}  // namespace probeless::occlusion
