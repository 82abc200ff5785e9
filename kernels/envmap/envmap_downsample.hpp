#pragma once
// Box downsampling of a keyframe's faces by an integer factor (envmap_downsample.cl).
#include "kernels/envmap/envmap_types.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::envmap {

class EnvmapDownsample {
 public:
  explicit EnvmapDownsample(ComputeContext& ctx);
  // texels: n x 6n; out: m x 6m, m = face_size (n must be a multiple of it). Enqueues only.
  void run(const DeviceImage<float, 4>& texels, int face_size, DeviceImage<float, 4>& out);

 private:
  ComputeContext& ctx_;
  ::cl::Kernel kernel_;
};

ImageRGBAF envmap_downsample_reference(const ImageRGBAF& texels, int face_size);

}  // namespace probeless::envmap
