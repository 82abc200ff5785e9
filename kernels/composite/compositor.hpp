#pragma once
// The final stage: the virtual object's colour over the real frame through the occlusion
// matte, all on the device (docs/opencl.md). Rounding: half up, exactly as composite_reference.
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless {

class Compositor {
 public:
  explicit Compositor(ComputeContext& ctx);

  // out = alpha * virtual_rgba.rgb + (1 - alpha) * real_rgb per pixel (the renderer's own
  // alpha channel is ignored: the matte already says where the object is). `out` is resized
  // to the inputs; throws std::invalid_argument when the inputs differ in size.
  void process(const DeviceImageRGB8& real_rgb, const DeviceImageRGBA8& virtual_rgba,
               const DeviceImageF& alpha, DeviceImageRGB8& out);
  // The matte as 8 bits (round(alpha * 255)) for file output.
  void matte8(const DeviceImageF& alpha, DeviceImageGray8& out);

 private:
  ComputeContext& ctx_;
  ::cl::Kernel composite_;
  ::cl::Kernel matte_;
};

}  // namespace probeless
