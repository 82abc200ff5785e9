#pragma once
// CPU reference of kernels/composite/hdr_compositor.cl (docs/compositing.md): compositing in
// the light model's radiance units, bit-exact with the device.
//
// Differential rendering (Debevec 1998, "Rendering synthetic objects into real scenes";
// Walton 2019 thesis ch. 6): the real frame is taken back to radiance through the colour
// camera's estimated response, the virtual layer is composited there, and the result is
// re-exposed through the same response, so the object looks filmed by that camera.
//
// The virtual layer is ONE float RGBA image, premultiplied (what a depth-tested render into a
// target cleared to 0 gives, and what averaging MSAA samples keeps):
//   object surface sample    writes (radiance, 1)        category "virtual"
//   shadow receiver sample   writes (signed delta, 0)    category "sum": L(with) - L(without)
//   nothing                  leaves (0, 0)               category "real"
// so a pixel holds rgb = c * object + (1 - c) * delta and a = c, the object's coverage, and
// one formula covers every mix of the three (the object's edge over its own shadow too):
//   out = m * rgb + (1 - m * c) * real                  (radiance, per channel)
// with m the occlusion matte: the visibility of whatever virtual layer the pixel has.
#include <array>
#include <cstdint>
#include <vector>

#include "core/image.hpp"

namespace probeless {

// The colour camera as the compositor models it (docs/lighting.md, kernels/hdr/
// colour_exposure.hpp): linear = (c / 255)^gamma, radiance = exposure[c] * linear.
struct CameraResponse {
  std::array<double, 3> exposure{1.0, 1.0, 1.0};  // e per channel, from ColourExposureEstimator
  double gamma = 2.2;  // the thesis's inverse gamma (and the sRGB curve's usual approximation)
};

// Throws std::invalid_argument unless every exposure is finite and in [1e-30, 1e30] (so that
// it and its reciprocal are normal floats) and gamma is finite and in (0, 10].
void validate(const CameraResponse& camera);

// The 8-bit <-> linear curve for one gamma, as tables shared by the reference and the device.
//   decode(v) = (v / 255)^gamma, rounded to float once.
//   encode(x) = round(255 * clamp(x, 0, 1)^(1 / gamma)), half up, defined exactly as the number
//   of thresholds t[v] = ((v - 0.5) / 255)^gamma (v = 1..255, rounded to float) that are <= x.
// encode needs no pow, and on the device no search: x's float bits >> kIndexShift (exponent and
// 7 mantissa bits, 128 entries per octave, where the curve moves less than 1 DN) pick an entry
// holding the threshold count at the entry's start and the next threshold. One compare gives
// the count when no entry spans two thresholds (steps() == 1 for every gamma >= 1: an entry
// spans at most 255 / (256 gamma) DN); gamma < 1 takes steps() - 1 more single steps. Integer
// arithmetic on the bits: the same entry on every device, so the result is the threshold count, bit
// for bit.
class CameraCurve {
 public:
  static constexpr int kIndexShift = 16;

  explicit CameraCurve(double gamma);  // throws std::invalid_argument like validate()

  double gamma() const { return gamma_; }
  float decode(std::uint8_t v) const { return decode_[v]; }
  std::uint8_t encode(float x) const;  // NaN and x <= 0 give 0; x >= 1 gives 255
  // The table path the device takes (the kernel's encode3), for the tests to compare.
  std::uint8_t encode_fast(float x) const;

  const std::array<float, 256>& decode_table() const { return decode_; }
  // 257 entries: [0] = 0 (unused), [v] = t[v], [256] = +infinity (a step past 255 never lands).
  const std::array<float, 257>& thresholds() const { return thresholds_; }
  // Entry j (0..index_last()) covers the floats whose bits >> kIndexShift are index_base() + j;
  // smaller x clamp to entry 0 and 1.0 is the last. Two words per entry: the count at the
  // entry's start (0 for entry 0) and the bits of the next threshold.
  const std::vector<std::uint32_t>& entries() const { return entries_; }
  int index_base() const { return index_base_; }
  int index_last() const { return index_last_; }
  int steps() const { return steps_; }  // >= 1

 private:
  double gamma_;
  std::array<float, 256> decode_{};
  std::array<float, 257> thresholds_{};
  std::vector<std::uint32_t> entries_;
  int index_base_ = 0;
  int index_last_ = 0;
  int steps_ = 1;
};

// What the device receives per channel: e and 1 / e as floats.
struct ExposureFactors {
  std::array<float, 3> e{};
  std::array<float, 3> inverse_e{};
};
ExposureFactors exposure_factors(const CameraResponse& camera);  // validates first

// One channel, before gamma: the composited radiance over e, clamped to [0, 1] (NaN -> 0).
//   real radiance R = e * decode(real8)   (a clipped channel, 255, is taken at the clip, e)
//   out = m * layer + (1 - m * c) * R, clamped at 0 radiance
// with m = matte and c = coverage, each clamped to [0, 1] with NaN as 0. The order of
// operations is the kernel's (contraction off on the device, none in ISO C++).
float hdr_composite_linear(std::uint8_t real8, float layer, float coverage, float matte, float e,
                           float inverse_e, const CameraCurve& curve);
// encode(hdr_composite_linear(...)), except that a pixel whose matte is 0 (or NaN, or
// negative) returns real8 untouched: the virtual layer is absent or hidden there.
std::uint8_t hdr_composite_channel(std::uint8_t real8, float layer, float coverage, float matte,
                                   float e, float inverse_e, const CameraCurve& curve);

// The whole frame: layer is premultiplied radiance + coverage (above), matte the occlusion
// stage's visibility. Throws std::invalid_argument when sizes differ or `camera` is invalid.
ImageRGB8 hdr_composite_reference(const ImageRGB8& real_rgb, const Image<float, 4>& layer,
                                  const ImageF& matte, const CameraResponse& camera);

}  // namespace probeless
