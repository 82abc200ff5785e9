#pragma once
// The device stage of hole_core_reference.hpp: the real depth with the cores of wide holes set
// nearer than anything, before CVF's depth test. Two small kernels (a sliding count along the rows,
// then the columns).
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::occlusion {

class HoleCoreFill {
 public:
  explicit HoleCoreFill(ComputeContext& ctx);
  // The filled copy of `depth` for a window radius >= 1 px (valid until the next call; else
  // std::invalid_argument); enqueues and does not wait.
  const DeviceImage<std::uint16_t, 1>& run(const DeviceImage<std::uint16_t, 1>& depth, int radius);

 private:
  ComputeContext& ctx_;
  ::cl::Kernel rows_, fill_;
  DeviceImage<std::uint8_t, 1> row_cores_;
  DeviceImage<std::uint16_t, 1> filled_;
};

}  // namespace probeless::occlusion
