#include "kernels/occlusion/baselines/guided_matte_reference.hpp"

#include <algorithm>

#include "kernels/occlusion/common/categorise_reference.hpp"
#include "kernels/occlusion/common/guided_filter_reference.hpp"

namespace probeless::occlusion {

float guided_matte_value(Category c) {
  return c == Category::Behind ? 1.0F : c == Category::Process ? 0.5F : 0.0F;
}

ImageF guided_matte_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                              const ImageF& virtual_depth_mm, const GuidedMatteParams& params) {
  const auto cats = categorise_reference(real_depth_mm, virtual_depth_mm, params.categorise);
  ImageF matte(colour.width(), colour.height());
  for (int y = 0; y < matte.height(); ++y)
    for (int x = 0; x < matte.width(); ++x)
      matte.at(x, y) = guided_matte_value(static_cast<Category>(cats.at(x, y)));
  auto q = guided_filter_reference(guide_from_rgb8(colour), matte, params.filter);
  for (int y = 0; y < q.height(); ++y)
    for (int x = 0; x < q.width(); ++x)
      q.at(x, y) = virtual_depth_mm.at(x, y) > 0.0F ? std::clamp(q.at(x, y), 0.0F, 1.0F) : 0.0F;
  return q;
}

}  // namespace probeless::occlusion
