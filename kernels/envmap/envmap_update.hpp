#pragma once
// Updates an environment-map keyframe from one HDR-converted fisheye frame: every texel the
// fisheye sees, by the Kalman or the best-score rule (envmap_update.cl; docs/light-capture.md).
#include "kernels/envmap/envmap_types.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::envmap {

class EnvmapUpdate {
 public:
  EnvmapUpdate(ComputeContext& ctx, const UpdateParams& params = {});
  const UpdateParams& params() const { return params_; }

  // image: the converted frame (rgb radiance, a quality, 0 = unusable). texels and pending:
  // n x 6n; pending holds the best-score rule's samples of the current cycle and must start
  // zeroed (the Kalman rule ignores it). publish: this frame ends a bracket cycle (best-score
  // writes the cycle's best samples into texels and clears pending). Enqueues only.
  void update(const DeviceImage<float, 4>& image, const FisheyeView& view, bool publish,
              DeviceImage<float, 4>& texels, DeviceImage<float, 4>& pending);

 private:
  ComputeContext& ctx_;
  UpdateParams params_;
  ::cl::Kernel kernel_;
};

}  // namespace probeless::envmap
