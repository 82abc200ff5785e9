#pragma once
// Saturated / zero-valued pixel counts of a raw linear frame: what the bracket sequencer's
// auto-exposure rules read (thesis ch. 5; docs/bracketing.md). Here in core, not in
// drivers/bracket, so that the OpenCL reduction (kernels/hdr/exposure_count) and the
// sequencer share one definition; count_exposure is that reduction's CPU reference.
#include <cstddef>
#include <cstdint>

#include "core/image.hpp"

namespace probeless {

// Counts over one frame. near_saturated / near_zero predict the next stop (pixels that one
// stop more would saturate, one stop less would zero; they include the saturated / zero ones)
// and keep L and H from stepping into an exposure they would step straight back out of. Left
// at 0 they give the thesis's rule exactly.
struct ExposureStats {
  std::size_t pixels = 0;
  std::size_t saturated = 0;  // any channel at full scale
  std::size_t zero = 0;       // any channel at or below the black level
  std::size_t near_saturated = 0;
  std::size_t near_zero = 0;
  bool operator==(const ExposureStats&) const = default;
};

// The counts' tests as integer thresholds on the signal s = raw - black of a channel (raw
// values are integers, so these are exact): a pixel counts when any channel passes.
struct ExposureThresholds {
  int saturated_signal = 0;       // s >= this: at full scale (raw >= 2^bits - 1)
  int zero_signal = 0;            // s <= this (0): at or below the black level
  int near_saturated_signal = 0;  // s >= this: doubled, it would saturate
  int near_zero_signal = 0;       // s <= this: halved, it would read zero
};

// The noise widens the predictions so that L and H do not flicker between two stops:
// near_zero takes the pixels whose halved signal read noise could take to zero (signal <=
// 1 + 6 sigma_read), near_saturated those whose doubled signal noise at full scale could
// saturate (2 signal + 3 sigma_full >= range). 0 and 0: the noise-free predictions.
// Throws std::invalid_argument for a bit depth outside [1, 16] or black level >= full scale.
ExposureThresholds exposure_thresholds(int bit_depth, std::uint16_t black_level,
                                       double read_noise_dn = 0.0,
                                       double full_scale_noise_dn = 0.0);

ExposureStats count_exposure(const ImageRGB16& raw, int bit_depth, std::uint16_t black_level,
                             double read_noise_dn = 0.0, double full_scale_noise_dn = 0.0);

// The same counts pixel by pixel: the plain statement of the rule, which count_exposure (eight
// pixels at a time) must equal exactly (tests).
ExposureStats count_exposure_per_pixel(const ImageRGB16& raw, int bit_depth,
                                       std::uint16_t black_level, double read_noise_dn = 0.0,
                                       double full_scale_noise_dn = 0.0);

}  // namespace probeless
