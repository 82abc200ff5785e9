#include "kernels/occlusion/baselines/direct_matte_reference.hpp"

#include <stdexcept>

namespace probeless::occlusion {

float direct_alpha(std::uint16_t real_mm, float virtual_mm, UnknownDepth unknown,
                   float tolerance_mm) {
  if (!(virtual_mm > 0.0F)) return 0.0F;
  if (real_mm == 0) return unknown == UnknownDepth::Visible ? 1.0F : 0.0F;
  const float limit = virtual_mm - tolerance_mm;
  return static_cast<float>(real_mm) >= limit ? 1.0F : 0.0F;
}

ImageF direct_matte_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                              UnknownDepth unknown, const CategoriseParams& tolerance) {
  const int w = real_depth_mm.width(), h = real_depth_mm.height();
  if (virtual_depth_mm.width() != w || virtual_depth_mm.height() != h)
    throw std::invalid_argument("direct_matte_reference: real and virtual depth sizes differ");
  ImageF alpha(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      alpha.at(x, y) = direct_alpha(real_depth_mm.at(x, y), virtual_depth_mm.at(x, y), unknown,
                                    depth_tolerance_mm(tolerance, virtual_depth_mm.at(x, y)));
  return alpha;
}

}  // namespace probeless::occlusion
