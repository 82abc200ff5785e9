#pragma once
// The guided filter with a colour guide on the device (guided_filter.cl), in two passes:
// coefficients (a, b) per window, then their window means applied to the guide. The input
// arrives packed with the guide as (r, g, b, p) so both passes read one buffer per pixel.
// guided_filter_reference.hpp is the CPU twin.
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::occlusion {

using DeviceImageF4 = DeviceImage<float, 4>;

class GuidedFilter {
 public:
  enum class Output {
    MeanCoefficients = 0,    // stop at the window means of (a, b) (fast filter: upsample next)
    VisibilityFromCost = 1,  // virtual > 0 ? clamp(1 - q) : 0
    Visibility = 2,          // virtual > 0 ? clamp(q) : 0
    Raw = 3,                 // q
  };
  // Tiles of 16 x 16 outputs: on PoCL under load, 16x16 took half the time of 64x16 and
  // 32x32 for the full-resolution feather filter (docs/occlusion.md "Speed").
  static constexpr int kTileWidth = 16;
  static constexpr int kTileHeight = 16;

  GuidedFilter(ComputeContext& ctx, int radius, float eps, Output output);
  int radius() const { return radius_; }

  // ab = per-window coefficients of the packed guide+input.
  void coefficients(const DeviceImageF4& guide_p, DeviceImageF4& ab);
  // MeanCoefficients: writes mean_ab. Other outputs: writes out from the means and guide_p's
  // colour (virtual_mm needed for the visibility outputs).
  void apply(const DeviceImageF4& ab, DeviceImageF4* mean_ab, const DeviceImageF4* guide_p,
             const DeviceImageF* virtual_mm, DeviceImageF* out);

 private:
  void enqueue(::cl::Kernel& k, int w, int h);

  ComputeContext& ctx_;
  int radius_;
  float eps_;
  Output output_;
  ::cl::Kernel coefficients_;
  ::cl::Kernel apply_;
};

}  // namespace probeless::occlusion
