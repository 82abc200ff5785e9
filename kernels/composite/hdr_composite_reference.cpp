#include "kernels/composite/hdr_composite_reference.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "kernels/composite/composite_reference.hpp"

namespace probeless {
namespace {

void check_gamma(double gamma, const char* who) {
  // Below 1 the device's encode takes extra steps (still exact); above 10 the encode table
  // passes 11 500 entries, and nothing is a camera's curve any more.
  if (!(std::isfinite(gamma) && gamma > 0.0 && gamma <= 10.0))
    throw std::invalid_argument(
        fmt::format("{}: gamma {} must be finite and in (0, 10]", who, gamma));
}

}  // namespace

void validate(const CameraResponse& camera) {
  for (int c = 0; c < 3; ++c) {
    const double e = camera.exposure[static_cast<std::size_t>(c)];
    // Both e and 1 / e must be normal floats: the device multiplies by 1 / e, and a denormal
    // (flushed to 0 by some devices) would differ from the reference.
    if (!(std::isfinite(e) && e >= 1e-30 && e <= 1e30))
      throw std::invalid_argument(fmt::format(
          "HDR composite: exposure e[{}] = {} must be finite and in [1e-30, 1e30]", c, e));
  }
  check_gamma(camera.gamma, "HDR composite");
}

CameraCurve::CameraCurve(double gamma) : gamma_(gamma) {
  check_gamma(gamma, "CameraCurve");
  for (int v = 0; v < 256; ++v) decode_[v] = static_cast<float>(std::pow(v / 255.0, gamma));
  thresholds_[0] = 0.0F;
  for (int v = 1; v < 256; ++v)
    thresholds_[v] = static_cast<float>(std::pow((v - 0.5) / 255.0, gamma));
  thresholds_[256] = std::numeric_limits<float>::infinity();

  // Entry 0 starts at the power of two at or below t[1], so every smaller x (counted 0) may
  // share it; gamma <= 10 keeps that a normal float (t[1] >= 510^-10).
  const int low_exponent = static_cast<int>(std::floor(std::log2(thresholds_[1])));
  index_base_ = (127 + low_exponent) << (23 - kIndexShift);
  index_last_ = (std::bit_cast<std::uint32_t>(1.0F) >> kIndexShift) - index_base_;
  const auto start = [this](int j) {
    return std::bit_cast<float>(static_cast<std::uint32_t>(index_base_ + j) << kIndexShift);
  };
  entries_.assign(2 * static_cast<std::size_t>(index_last_ + 1), 0);
  steps_ = 1;
  for (int j = 0; j <= index_last_; ++j) {
    const int count = j == 0 ? 0 : encode(start(j));
    entries_[2 * static_cast<std::size_t>(j)] = static_cast<std::uint32_t>(count);
    entries_[2 * static_cast<std::size_t>(j) + 1] =
        std::bit_cast<std::uint32_t>(thresholds_[static_cast<std::size_t>(count) + 1]);
    // The most any x of this entry needs: the count at its last float (1.0 for the last).
    const float end = j == index_last_ ? 1.0F : std::nextafter(start(j + 1), 0.0F);
    steps_ = std::max(steps_, encode(end) - count);
  }
}

std::uint8_t CameraCurve::encode(float x) const {
  if (!(x > 0.0F)) return 0;  // NaN too
  return static_cast<std::uint8_t>(
      std::upper_bound(thresholds_.begin() + 1, thresholds_.end() - 1, x) -
      (thresholds_.begin() + 1));
}

std::uint8_t CameraCurve::encode_fast(float x) const {
  x = composite_weight(x);  // [0, 1], NaN as 0
  const int j =
      std::clamp(static_cast<int>(std::bit_cast<std::uint32_t>(x) >> kIndexShift) - index_base_, 0,
                 index_last_);
  const std::size_t e = 2 * static_cast<std::size_t>(j);
  std::uint32_t v = entries_[e] + (x >= std::bit_cast<float>(entries_[e + 1]) ? 1 : 0);
  for (int k = 1; k < steps_; ++k) v += x >= thresholds_[v + 1] ? 1 : 0;
  return static_cast<std::uint8_t>(v);
}

ExposureFactors exposure_factors(const CameraResponse& camera) {
  validate(camera);
  ExposureFactors f;
  for (std::size_t c = 0; c < 3; ++c) {
    f.e[c] = static_cast<float>(camera.exposure[c]);
    f.inverse_e[c] = static_cast<float>(1.0 / camera.exposure[c]);
  }
  return f;
}

float hdr_composite_linear(std::uint8_t real8, float layer, float coverage, float matte, float e,
                           float inverse_e, const CameraCurve& curve) {
  const float m = composite_weight(matte);
  const float c = composite_weight(coverage);
  // A clipped channel (255) decodes to 1: the real radiance is taken at the clip, the least it
  // can be, and a shadow darkens it by its full delta. Walton 2019 ch. 6 gives no rule for
  // clipped pixels; this one keeps a shadow on a blown-out surface visible, at least as dark
  // as the truth (docs/compositing.md "Clamping and clipped pixels").
  const float real = e * curve.decode(real8);
  const float w = m * c;
  const float out = m * layer + (1.0F - w) * real;
  // Clamped at 0 radiance (a shadow delta larger than the real radiance, e.g. from a light
  // model brighter than the camera saw), then to the displayable range.
  return composite_weight(out * inverse_e);  // NaN (from a NaN layer) as 0
}

std::uint8_t hdr_composite_channel(std::uint8_t real8, float layer, float coverage, float matte,
                                   float e, float inverse_e, const CameraCurve& curve) {
  if (!(matte > 0.0F)) return real8;
  return curve.encode(hdr_composite_linear(real8, layer, coverage, matte, e, inverse_e, curve));
}

ImageRGB8 hdr_composite_reference(const ImageRGB8& real_rgb, const Image<float, 4>& layer,
                                  const ImageF& matte, const CameraResponse& camera) {
  const int w = real_rgb.width(), h = real_rgb.height();
  if (layer.width() != w || layer.height() != h || matte.width() != w || matte.height() != h)
    throw std::invalid_argument("hdr_composite_reference: real, layer and matte differ in size");
  const ExposureFactors f = exposure_factors(camera);
  const CameraCurve curve(camera.gamma);
  ImageRGB8 out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        out.at(x, y, c) = hdr_composite_channel(
            real_rgb.at(x, y, c), layer.at(x, y, c), layer.at(x, y, 3), matte.at(x, y),
            f.e[static_cast<std::size_t>(c)], f.inverse_e[static_cast<std::size_t>(c)], curve);
  return out;
}

}  // namespace probeless
