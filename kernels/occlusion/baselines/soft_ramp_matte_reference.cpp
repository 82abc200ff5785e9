#include "kernels/occlusion/baselines/soft_ramp_matte_reference.hpp"

#include <algorithm>

namespace probeless::occlusion {

ImageF soft_ramp_matte_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                                 const SoftRampParams& params) {
  const int w = real_depth_mm.width(), h = real_depth_mm.height(), r = params.smoothing_radius;
  ImageF alpha(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = virtual_depth_mm.at(x, y);
      if (!(v > 0.0F)) continue;
      float sum = 0.0F;
      int n = 0;
      for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
        for (int i = std::max(0, x - r); i <= std::min(w - 1, x + r); ++i)
          if (const std::uint16_t d = real_depth_mm.at(i, j); d != 0) {
            sum += static_cast<float>(d);
            ++n;
          }
      if (n == 0) {
        alpha.at(x, y) = 1.0F;
        continue;
      }
      const float d = sum / static_cast<float>(n);
      alpha.at(x, y) =
          std::clamp((d - v) / (2.0F * params.relative_half_width * v) + 0.5F, 0.0F, 1.0F);
    }
  return alpha;
}

}  // namespace probeless::occlusion
