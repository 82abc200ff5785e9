#include "kernels/occlusion/baselines/crabb_matte_reference.hpp"

namespace probeless::occlusion {

double mean_virtual_depth(const ImageF& virtual_depth_mm) {
  double sum = 0.0;
  std::size_t n = 0;
  for (float v : virtual_depth_mm.elements())
    if (v > 0.0F) {
      sum += v;
      ++n;
    }
  return n ? sum / static_cast<double>(n) : 0.0;
}

ImageF crabb_matte_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm) {
  const auto threshold = static_cast<float>(mean_virtual_depth(virtual_depth_mm));
  ImageF alpha(real_depth_mm.width(), real_depth_mm.height());
  for (int y = 0; y < alpha.height(); ++y)
    for (int x = 0; x < alpha.width(); ++x) {
      if (!(virtual_depth_mm.at(x, y) > 0.0F)) continue;
      const std::uint16_t d = real_depth_mm.at(x, y);
      alpha.at(x, y) = d != 0 && static_cast<float>(d) < threshold ? 0.0F : 1.0F;
    }
  return alpha;
}

}  // namespace probeless::occlusion
