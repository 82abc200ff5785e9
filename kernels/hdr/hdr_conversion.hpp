#pragma once
// HDR conversion of the upward fisheye's raw linear frames (thesis ch. 5; issue #5 deliver 2;
// docs/lighting.md). One frame of the L-M-H-M bracket becomes radiance up to a constant, with
// a per-pixel quality that the environment-map update (kernels/envmap, branch light-envmap)
// reads: 0 = never use this sample (saturated, black, outside the image circle).
//
// CONTRACT with kernels/envmap (agreed in the light-capture briefs; add members, do not change
// these): HdrConversionParams' four fields and their meaning, the constructor, and convert()'s
// signature and output (rgb = linear radiance up to a constant, a = quality in [0,1], 0 only
// where the sample must never be used).
#include <cstdint>

#include "core/exposure.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless {

struct HdrConversionParams {
  float saturation_fraction = 0.95f;  // raw - black >= this * (white - black) in any channel
                                      // -> saturated (the sensor response bends before full
                                      // scale; white = 2^bit_depth - 1)
  int black_margin = 2;               // raw - black <= margin in all channels -> black (no
                                      // signal above read noise)
  // Image circle, in pixels (OpenCV centres: (0,0) is the top-left pixel's centre): pixels
  // farther than circle_radius from (circle_cx, circle_cy) are invalid (vignetting border
  // crop). radius 0 = no crop.
  float circle_cx = 0, circle_cy = 0, circle_radius = 0;
};

// Throws std::invalid_argument unless 0 < saturation_fraction <= 1, black_margin >= 0 and
// circle_radius >= 0 (all finite).
void validate(const HdrConversionParams& params);

// What convert() derives per frame, shared by the kernel's host side and the CPU reference so
// that the flags are integer comparisons both sides agree on exactly.
struct HdrConversionConstants {
  int range = 0;             // white - black, white = 2^bit_depth - 1
  int saturated_signal = 0;  // raw - black >= this in any channel -> saturated
  int black_margin = 0;      // raw - black <= this in all channels -> black
  float radiance_scale = 0;  // 1 / (range * E)
  float inv_range = 0;       // 1 / range, for the normalised level of the quality hat
  bool crop = false;         // image circle given
  float circle_cx = 0, circle_cy = 0, circle_radius2 = 0;
};
// Validates as convert() does (std::invalid_argument).
HdrConversionConstants hdr_conversion_constants(int bit_depth, std::uint16_t black_level,
                                                const Exposure& exposure,
                                                const HdrConversionParams& params);
// The least quality a usable sample gets (the hat reaches 0 only at the ends of the range).
inline constexpr float kMinUsableQuality = 1e-6f;

class HdrConversion {
 public:
  HdrConversion(ComputeContext& ctx, HdrConversionParams params = {});

  // raw: the fisheye frame uploaded as DeviceImage<std::uint16_t,3>; out is resized to it.
  // out.rgb = max(raw - black, 0) / (white - black) / (exposure.time_s * exposure.gain()):
  //           linear radiance up to a constant (white = 2^bit_depth - 1).
  // out.a   = quality in [0,1]: 0 where saturated, black or outside the circle (must never be
  //           used), else the hat 2 min(x, 1 - x) of the normalised level x of the pixel's
  //           highest channel (highest mid-range), floored at a tiny positive value so a
  //           usable sample never reads 0. The best-score rule ranks samples by it and the
  //           Kalman filter may use it as a weight.
  // Enqueues, does not wait. Throws std::invalid_argument for bit_depth outside [1, 16],
  // black_level >= white, or an exposure whose value (time x gain) is not finite and > 0.
  void convert(const DeviceImage<std::uint16_t, 3>& raw, int bit_depth, std::uint16_t black_level,
               const Exposure& exposure, DeviceImage<float, 4>& out);

  const HdrConversionParams& params() const { return params_; }

 private:
  ComputeContext& ctx_;
  HdrConversionParams params_;
  ::cl::Kernel kernel_;
};

}  // namespace probeless
