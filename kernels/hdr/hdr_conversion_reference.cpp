#include "kernels/hdr/hdr_conversion_reference.hpp"

#include <algorithm>

namespace probeless {

std::array<float, 4> hdr_convert_pixel(const std::uint16_t* rgb, int x, int y,
                                       std::uint16_t black_level, const HdrConversionConstants& c) {
  int signal[3];
  for (int ch = 0; ch < 3; ++ch) signal[ch] = static_cast<int>(rgb[ch]) - black_level;
  const int peak = std::max({signal[0], signal[1], signal[2]});
  bool usable = peak < c.saturated_signal && peak > c.black_margin;
  if (c.crop) {
    const float dx = static_cast<float>(x) - c.circle_cx;
    const float dy = static_cast<float>(y) - c.circle_cy;
    const float dx2 = dx * dx;  // separate statements: no fused multiply-add
    const float dy2 = dy * dy;
    const float d2 = dx2 + dy2;
    usable = usable && d2 <= c.circle_radius2;
  }
  float quality = 0.0f;
  if (usable) {
    const float level = static_cast<float>(peak) * c.inv_range;
    quality = std::max(2.0f * std::min(level, 1.0f - level), kMinUsableQuality);
  }
  std::array<float, 4> out{};
  for (int ch = 0; ch < 3; ++ch)
    out[ch] = static_cast<float>(std::max(signal[ch], 0)) * c.radiance_scale;
  out[3] = quality;
  return out;
}

ImageRGBAF hdr_conversion_reference(const ImageRGB16& raw, int bit_depth, std::uint16_t black_level,
                                    const Exposure& exposure, const HdrConversionParams& params) {
  const HdrConversionConstants c =
      hdr_conversion_constants(bit_depth, black_level, exposure, params);
  ImageRGBAF out(raw.width(), raw.height());
  for (int y = 0; y < raw.height(); ++y)
    for (int x = 0; x < raw.width(); ++x) {
      const auto px = hdr_convert_pixel(&raw.at(x, y, 0), x, y, black_level, c);
      std::copy(px.begin(), px.end(), &out.at(x, y, 0));
    }
  return out;
}

}  // namespace probeless
