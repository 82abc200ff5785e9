#pragma once
// The bracket sequencer's saturated / zero-valued pixel counts of a raw fisheye frame, on the
// device where the frame already is (issue #5 deliver 1; docs/bracketing.md). Same counts as
// core's count_exposure, its CPU reference (tests/kernels/hdr/exposure_count_test.cpp).
#include <cstdint>

#include "core/exposure_count.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless {

class ExposureCount {
 public:
  explicit ExposureCount(ComputeContext& ctx);

  // Enqueues the reduction and waits for its few bytes of result (the sequencer needs the
  // counts before it picks the exposure after next). Arguments as count_exposure; throws
  // std::invalid_argument for the same bad bit depth / black level.
  ExposureStats count(const DeviceImage<std::uint16_t, 3>& raw, int bit_depth,
                      std::uint16_t black_level, double read_noise_dn = 0.0,
                      double full_scale_noise_dn = 0.0);

 private:
  static constexpr int kGroupSize = 64;
  static constexpr int kMaxGroups = 64;  // enough to keep every compute unit busy

  ComputeContext& ctx_;
  ::cl::Kernel kernel_;
  ::cl::Buffer partials_;  // kMaxGroups x uint4
};

}  // namespace probeless
