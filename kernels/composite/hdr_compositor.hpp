#pragma once
// HDR compositing (issue #6 item 4; docs/compositing.md): the virtual layer, rendered in the
// light model's radiance units, is composited into the colour frame in radiance and the result
// re-exposed with the colour camera's own exposure, white balance and gamma, so the object
// looks filmed by that camera and follows its auto-exposure. Differential rendering after
// Debevec 1998 ("Rendering synthetic objects into real scenes") and Walton 2019, ch. 6.
// Bit-exact with hdr_composite_reference (kernels/composite/hdr_composite_reference.hpp).
#include <optional>

#include "kernels/composite/hdr_composite_reference.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless {

class HdrCompositor {
 public:
  explicit HdrCompositor(ComputeContext& ctx);

  // real_rgb: the colour frame as the camera encoded it (gamma, its exposure and white
  //   balance).
  // layer: the virtual layer, premultiplied float RGBA in radiance units: rgb = c * object
  //   radiance + (1 - c) * differential delta (signed: a shadow is negative), a = c, the
  //   object's coverage (hdr_composite_reference.hpp spells out the categories).
  // matte: the occlusion stage's visibility of the virtual layer, in [0, 1] (soft edges);
  //   it hides the delta as well as the object (a real hand over the virtual shadow).
  // camera: the colour camera's exposure e per channel (ColourExposureEstimator) and gamma.
  // out (resized to the inputs) = re-exposed m * layer + (1 - m * c) * real, clamped at 0
  // radiance; pixels with matte 0 keep their bytes. Throws std::invalid_argument when sizes
  // differ or `camera` is invalid (validate()). Enqueues on ctx's queue and does not wait.
  // `objects`: the matte is 0 outside this rectangle (OcclusionInputs::objects), so only its
  // rows are visited after the copy of the frame.
  void process(const DeviceImageRGB8& real_rgb, const DeviceImage<float, 4>& layer,
               const DeviceImageF& matte, const CameraResponse& camera, DeviceImageRGB8& out,
               const std::optional<PixelRect>& objects = std::nullopt);

 private:
  // (Re)builds and uploads the curve's tables on a change of gamma, and the kernel when the
  // number of encode steps (a -D option) changes with it.
  void use_gamma(double gamma);

  static constexpr int kPixelsPerItem = 16;  // PIXELS in hdr_compositor.cl

  ComputeContext& ctx_;
  ::cl::Kernel kernel_;
  std::optional<CameraCurve> curve_;
  ::cl::Buffer decode_, thresholds_, entries_;
};

}  // namespace probeless
