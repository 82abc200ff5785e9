#include "core/exposure_count.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace probeless {

namespace {
// Doubles far outside the int range (absurd noise figures) saturate instead of overflowing.
int clamp_to_int(double v) {
  return static_cast<int>(std::clamp(v, -1e9, 1e9));
}
}  // namespace

ExposureThresholds exposure_thresholds(int bit_depth, std::uint16_t black_level,
                                       double read_noise_dn, double full_scale_noise_dn) {
  if (bit_depth < 1 || bit_depth > 16) throw std::invalid_argument("count_exposure: bit depth");
  const int full = (1 << bit_depth) - 1;
  if (black_level >= full) throw std::invalid_argument("count_exposure: black level");
  const int range = full - black_level;
  const double near_zero_limit = 1.0 + 6.0 * std::max(0.0, read_noise_dn);
  const double near_saturated_limit = range - 3.0 * std::max(0.0, full_scale_noise_dn);
  ExposureThresholds t;
  t.saturated_signal = range;
  t.zero_signal = 0;
  // Integer s: 2 s >= L  <=>  s >= ceil(L / 2);  s <= L  <=>  s <= floor(L).
  t.near_saturated_signal = clamp_to_int(std::ceil(near_saturated_limit / 2.0));
  t.near_zero_signal = clamp_to_int(std::floor(near_zero_limit));
  return t;
}

ExposureStats count_exposure(const ImageRGB16& raw, int bit_depth, std::uint16_t black_level,
                             double read_noise_dn, double full_scale_noise_dn) {
  const ExposureThresholds t =
      exposure_thresholds(bit_depth, black_level, read_noise_dn, full_scale_noise_dn);
  ExposureStats s;
  s.pixels = raw.pixel_count();
  const std::uint16_t* p = raw.data();
  for (std::size_t i = 0; i < s.pixels; ++i, p += 3) {
    int hi = p[0], lo = p[0];
    for (int c = 1; c < 3; ++c) {
      hi = std::max<int>(hi, p[c]);
      lo = std::min<int>(lo, p[c]);
    }
    // Any channel passes an upper test iff the highest does, a lower test iff the lowest does.
    hi -= black_level;
    lo -= black_level;
    s.saturated += hi >= t.saturated_signal;
    s.zero += lo <= t.zero_signal;
    s.near_saturated += hi >= t.near_saturated_signal;
    s.near_zero += lo <= t.near_zero_signal;
  }
  return s;
}

}  // namespace probeless
