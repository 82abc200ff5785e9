#include "kernels/hdr/hdr_conversion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "kernels/hdr/hdr_conversion_cl.hpp"

namespace probeless {

namespace {
constexpr int kPixelsPerItem = 4;  // hdr_conversion.cl: 4 pixels of a row per work-item
}  // namespace

void validate(const HdrConversionParams& p) {
  if (!(p.saturation_fraction > 0.0f && p.saturation_fraction <= 1.0f))
    throw std::invalid_argument("HDR conversion: saturation_fraction must be in (0, 1]");
  if (p.black_margin < 0) throw std::invalid_argument("HDR conversion: black_margin < 0");
  if (!(std::isfinite(p.circle_cx) && std::isfinite(p.circle_cy) &&
        std::isfinite(p.circle_radius) && p.circle_radius >= 0.0f))
    throw std::invalid_argument("HDR conversion: image circle must be finite, radius >= 0");
}

HdrConversionConstants hdr_conversion_constants(int bit_depth, std::uint16_t black_level,
                                                const Exposure& exposure,
                                                const HdrConversionParams& params) {
  validate(params);
  if (bit_depth < 1 || bit_depth > 16)
    throw std::invalid_argument("HDR conversion: bit depth " + std::to_string(bit_depth) +
                                " outside [1, 16]");
  const int white = (1 << bit_depth) - 1;
  if (black_level >= white)
    throw std::invalid_argument("HDR conversion: black level " + std::to_string(black_level) +
                                " not below white " + std::to_string(white));
  const double e = exposure.value();
  if (!(std::isfinite(e) && e > 0.0))
    throw std::invalid_argument(
        "HDR conversion: exposure time x gain must be finite and > 0 (time " +
        std::to_string(exposure.time_s) + " s, gain " + std::to_string(exposure.gain_db) + " dB)");
  HdrConversionConstants c;
  c.range = white - black_level;
  // Integer threshold: signal >= fraction * range  <=>  signal >= ceil(fraction * range).
  c.saturated_signal =
      std::max(1, static_cast<int>(std::ceil(double{params.saturation_fraction} * c.range)));
  c.black_margin = params.black_margin;
  c.radiance_scale = static_cast<float>(1.0 / (c.range * e));
  if (!(std::isfinite(c.radiance_scale) && c.radiance_scale > 0.0f))
    throw std::invalid_argument("HDR conversion: exposure out of float range");
  c.inv_range = static_cast<float>(1.0 / c.range);
  c.crop = params.circle_radius > 0.0f;
  c.circle_cx = params.circle_cx;
  c.circle_cy = params.circle_cy;
  c.circle_radius2 = params.circle_radius * params.circle_radius;
  return c;
}

HdrConversion::HdrConversion(ComputeContext& ctx, HdrConversionParams params)
    : ctx_(ctx), params_(params) {
  validate(params_);
  kernel_ = ctx.kernel("hdr_conversion", cl_source::hdr_conversion, {}, "hdr_conversion");
}

void HdrConversion::convert(const DeviceImage<std::uint16_t, 3>& raw, int bit_depth,
                            std::uint16_t black_level, const Exposure& exposure,
                            DeviceImage<float, 4>& out) {
  const HdrConversionConstants c =
      hdr_conversion_constants(bit_depth, black_level, exposure, params_);
  const int w = raw.width(), h = raw.height();
  out.resize(ctx_.context(), w, h);
  if (out.empty()) return;
  int a = 0;
  kernel_.setArg(a++, raw.buffer());
  kernel_.setArg(a++, out.buffer());
  kernel_.setArg(a++, w);
  kernel_.setArg(a++, h);
  kernel_.setArg(a++, static_cast<int>(black_level));
  kernel_.setArg(a++, c.saturated_signal);
  kernel_.setArg(a++, c.black_margin);
  kernel_.setArg(a++, c.radiance_scale);
  kernel_.setArg(a++, c.inv_range);
  kernel_.setArg(a++, c.crop ? 1 : 0);
  kernel_.setArg(a++, c.circle_cx);
  kernel_.setArg(a++, c.circle_cy);
  kernel_.setArg(a++, c.circle_radius2);
  ctx_.run_2d(kernel_, (w + kPixelsPerItem - 1) / kPixelsPerItem, h);
}

}  // namespace probeless
