#include "kernels/occlusion/baselines/meta_soft_matte_reference.hpp"

#include <algorithm>

namespace probeless::occlusion {

ImageF meta_soft_matte_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                                 const MetaSoftParams& params) {
  const int w = real_depth_mm.width(), h = real_depth_mm.height(), r = params.radius;
  ImageF alpha(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = virtual_depth_mm.at(x, y);
      if (!(v > 0.0F)) continue;
      float lo = 0.0F, hi = 0.0F, sum = 0.0F;
      int n = 0;
      for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
        for (int i = std::max(0, x - r); i <= std::min(w - 1, x + r); ++i)
          if (const std::uint16_t d16 = real_depth_mm.at(i, j); d16 != 0) {
            const auto d = static_cast<float>(d16);
            lo = n ? std::min(lo, d) : d;
            hi = n ? std::max(hi, d) : d;
            sum += d;
            ++n;
          }
      if (n == 0) {
        alpha.at(x, y) = 1.0F;
        continue;
      }
      const float range = params.relative_range * v;
      auto vis = [&](float d) { return std::clamp((d - v) / range, 0.0F, 1.0F); };
      const float mean = sum / static_cast<float>(n);
      float a = vis(mean);
      const float vlo = vis(lo), vhi = vis(hi);
      if (vhi - vlo > params.blend_threshold) {
        const float t = (mean - lo) / (hi - lo);
        const float s = std::clamp(
            (t - params.foreground_level) / (params.background_level - params.foreground_level),
            0.0F, 1.0F);
        const float k = s * s * (3.0F - 2.0F * s);
        a = vlo + (vhi - vlo) * k;
      }
      alpha.at(x, y) = a;
    }
  return alpha;
}

}  // namespace probeless::occlusion
