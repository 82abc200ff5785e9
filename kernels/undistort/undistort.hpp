#pragma once
// Applies the colour camera's undistortion remap (undistort_map.hpp) on the device: the
// colour bilinearly, the depth registered to it by the nearest pixel (undistort.cl).
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"
#include "kernels/undistort/undistort_map.hpp"

namespace probeless {

class Undistort {
 public:
  // Uploads the map once. Frames must be the map's size.
  Undistort(ComputeContext& ctx, const UndistortMap& map);
  int width() const { return map_.width(); }
  int height() const { return map_.height(); }

  // Enqueue only; `out` is resized to the map. std::invalid_argument for another frame size.
  void colour(const DeviceImageRGB8& in, DeviceImageRGB8& out);
  void depth(const DeviceDepthImage& in, DeviceDepthImage& out);

 private:
  template <typename T, int C>
  void run(::cl::Kernel& kernel, const DeviceImage<T, C>& in, DeviceImage<T, C>& out);

  ComputeContext& ctx_;
  DeviceImage<float, 2> map_;
  ::cl::Kernel colour_, depth_;
};

}  // namespace probeless
