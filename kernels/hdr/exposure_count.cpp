#include "kernels/hdr/exposure_count.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>
#include <string>

#include "kernels/hdr/exposure_count_cl.hpp"

namespace probeless {

ExposureCount::ExposureCount(ComputeContext& ctx)
    : ctx_(ctx),
      kernel_(ctx.kernel("exposure_count", cl_source::exposure_count,
                         "-DGROUP_SIZE=" + std::to_string(kGroupSize), "exposure_count")),
      partials_(ctx.context(), CL_MEM_READ_WRITE,
                sizeof(cl_uint) * 4 * static_cast<std::size_t>(kMaxGroups)) {}

ExposureStats ExposureCount::count(const DeviceImage<std::uint16_t, 3>& raw, int bit_depth,
                                   std::uint16_t black_level, double read_noise_dn,
                                   double full_scale_noise_dn) {
  const ExposureThresholds t =
      exposure_thresholds(bit_depth, black_level, read_noise_dn, full_scale_noise_dn);
  ExposureStats stats;
  stats.pixels = raw.pixel_count();
  if (raw.empty()) return stats;
  if (stats.pixels > static_cast<std::size_t>(std::numeric_limits<int>::max() / 3))
    throw std::invalid_argument("exposure count: frame too large");
  const int pixels = static_cast<int>(stats.pixels);
  // 4 pixels per work-item and step (exposure_count.cl).
  const int groups = std::clamp((pixels / 4 + kGroupSize - 1) / kGroupSize, 1, kMaxGroups);
  int a = 0;
  kernel_.setArg(a++, raw.buffer());
  kernel_.setArg(a++, pixels);
  kernel_.setArg(a++, static_cast<int>(black_level));
  kernel_.setArg(a++, t.saturated_signal);
  kernel_.setArg(a++, t.zero_signal);
  kernel_.setArg(a++, t.near_saturated_signal);
  kernel_.setArg(a++, t.near_zero_signal);
  kernel_.setArg(a++, partials_);
  ctx_.queue().enqueueNDRangeKernel(kernel_, ::cl::NullRange,
                                    ::cl::NDRange(static_cast<std::size_t>(groups) * kGroupSize),
                                    ::cl::NDRange(kGroupSize));
  std::array<cl_uint, 4 * kMaxGroups> partial{};
  ctx_.queue().enqueueReadBuffer(partials_, CL_TRUE, 0, sizeof(cl_uint) * 4 * groups,
                                 partial.data());
  for (int g = 0; g < groups; ++g) {
    stats.saturated += partial[4 * g + 0];
    stats.zero += partial[4 * g + 1];
    stats.near_saturated += partial[4 * g + 2];
    stats.near_zero += partial[4 * g + 3];
  }
  return stats;
}

}  // namespace probeless
