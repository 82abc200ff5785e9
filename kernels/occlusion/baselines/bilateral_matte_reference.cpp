#include "kernels/occlusion/baselines/bilateral_matte_reference.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/occlusion/common/categorise_reference.hpp"

namespace probeless::occlusion {

ImageF bilateral_matte_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                                 const ImageF& virtual_depth_mm,
                                 const BilateralMatteParams& params) {
  const auto cats = categorise_reference(real_depth_mm, virtual_depth_mm, params.categorise);
  const int w = colour.width(), h = colour.height(), r = params.radius;
  const float ks = -0.5F / (params.sigma_space_px * params.sigma_space_px);
  const float kc = -0.5F / (params.sigma_colour * params.sigma_colour) / (255.0F * 255.0F);
  ImageF alpha(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto c = static_cast<Category>(cats.at(x, y));
      if (c == Category::Ignore) continue;
      if (c != Category::Process) {
        alpha.at(x, y) = c == Category::Behind ? 1.0F : 0.0F;
        continue;
      }
      float sum = 0.0F, wsum = 0.0F;
      for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
        for (int i = std::max(0, x - r); i <= std::min(w - 1, x + r); ++i) {
          const auto cq = static_cast<Category>(cats.at(i, j));
          if (cq != Category::Infront && cq != Category::Behind) continue;
          float d2 = 0.0F;
          for (int k = 0; k < 3; ++k) {
            const float d = float(colour.at(i, j, k)) - float(colour.at(x, y, k));
            d2 += d * d;
          }
          const float wq = std::exp(ks * float((i - x) * (i - x) + (j - y) * (j - y)) + kc * d2);
          sum += wq * (cq == Category::Behind ? 1.0F : 0.0F);
          wsum += wq;
        }
      alpha.at(x, y) = wsum > 0.0F ? sum / wsum : 0.5F;
    }
  return alpha;
}

}  // namespace probeless::occlusion
