#include "kernels/occlusion/foreground/foreground_estimate_reference.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace probeless::occlusion {

void validate(const ForegroundEstimateParams& p) {
  if (p.radius_px < 1 || p.radius_px > 16)
    throw std::invalid_argument("foreground estimate: radius " + std::to_string(p.radius_px) +
                                " px must be in [1, 16]");
  if (!(p.confident >= 0.0F && p.confident < 0.5F))
    throw std::invalid_argument("foreground estimate: confident " + std::to_string(p.confident) +
                                " must be in [0, 0.5)");
  if (!std::isfinite(p.gamma) || p.gamma <= 0.0 || p.gamma > 10.0)
    throw std::invalid_argument("foreground estimate: gamma " + std::to_string(p.gamma) +
                                " must be finite and in (0, 10]");
}

std::array<float, 256> decode_table(double gamma) {
  std::array<float, 256> t{};
  for (int v = 0; v < 256; ++v) t[v] = static_cast<float>(std::pow(v / 255.0, gamma));
  return t;
}

ImageRGB8 foreground_estimate_reference(const ImageRGB8& colour, const ImageF& virtual_depth_mm,
                                        const ImageF& visibility,
                                        const ForegroundEstimateParams& p) {
  validate(p);
  const int w = colour.width(), h = colour.height();
  if (virtual_depth_mm.width() != w || virtual_depth_mm.height() != h || visibility.width() != w ||
      visibility.height() != h)
    throw std::invalid_argument(
        "foreground estimate: colour, virtual depth and matte sizes differ");
  const auto decode = decode_table(p.gamma);
  const float inv_gamma = static_cast<float>(1.0 / p.gamma);
  const float lo = p.confident, hi = 1.0F - p.confident;
  ImageRGB8 out = colour;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float vis = visibility.at(x, y);
      if (!(virtual_depth_mm.at(x, y) > 0.0F) || !(vis > 0.0F && vis < 1.0F)) continue;
      // Same order of float operations as foreground_estimate.cl (contraction off there).
      float f[3] = {0, 0, 0}, b[3] = {0, 0, 0}, wf = 0.0F, wb = 0.0F;
      for (int dy = -p.radius_px; dy <= p.radius_px; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= h) continue;
        for (int dx = -p.radius_px; dx <= p.radius_px; ++dx) {
          const int xx = x + dx;
          if (xx < 0 || xx >= w || !(virtual_depth_mm.at(xx, yy) > 0.0F)) continue;
          const float v = visibility.at(xx, yy);
          const bool is_f = v <= lo, is_b = v >= hi;
          if (!is_f && !is_b) continue;
          const float wt = 1.0F / (1.0F + static_cast<float>(dx * dx + dy * dy));
          float* acc = is_f ? f : b;
          for (int c = 0; c < 3; ++c) acc[c] += wt * decode[colour.at(xx, yy, c)];
          (is_f ? wf : wb) += wt;
        }
      }
      if (wf == 0.0F || wb == 0.0F) continue;
      const float a = 1.0F - vis;  // the real occluder's opacity
      const float na = 1.0F - a;
      const float k = a / (a * a + na * na);
      for (int c = 0; c < 3; ++c) {
        const float fl = f[c] / wf, bl = b[c] / wb;
        const float r = decode[colour.at(x, y, c)] - a * fl - na * bl;
        const float fc = std::clamp(fl + k * r, 0.0F, 1.0F);
        out.at(x, y, c) =
            static_cast<std::uint8_t>(std::floor(255.0F * std::pow(fc, inv_gamma) + 0.5F));
      }
    }
  return out;
}

}  // namespace probeless::occlusion
