#include "kernels/occlusion/cvf/cvf_reference.hpp"

#include <algorithm>
#include <stdexcept>

#include "kernels/occlusion/common/categorise_reference.hpp"
#include "kernels/occlusion/common/guided_filter_reference.hpp"

namespace probeless::occlusion {

float cvf_cost(Category c, int bin, const ColourModels& models, bool models_valid,
               std::uint16_t real_mm, float virtual_mm) {
  switch (c) {
    case Category::Infront:
      return kCostInfront;
    case Category::Behind:
      return kCostBehind;
    case Category::Ignore:
      return kCostIgnore;
    case Category::Process:
      break;
  }
  if (!models_valid) {
    if (real_mm == 0) return 0.5F;
    return static_cast<float>(real_mm) < virtual_mm ? 1.0F : 0.0F;
  }
  const float p_in = static_cast<float>(models.infront[bin]) / models.infront_total();
  const float p_be = static_cast<float>(models.behind[bin]) / models.behind_total();
  return p_in + p_be > 0.0F ? p_in / (p_in + p_be) : 0.5F;
}

ImageF visibility_from_cost(const ImageF& filtered_cost, const ImageF& virtual_depth_mm) {
  ImageF alpha(filtered_cost.width(), filtered_cost.height());
  for (int y = 0; y < alpha.height(); ++y)
    for (int x = 0; x < alpha.width(); ++x)
      alpha.at(x, y) = virtual_depth_mm.at(x, y) > 0.0F
                           ? std::clamp(1.0F - filtered_cost.at(x, y), 0.0F, 1.0F)
                           : 0.0F;
  return alpha;
}

CvfTrace cvf_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                       const ImageF& virtual_depth_mm, const CvfParams& params) {
  const int w = colour.width(), h = colour.height();
  if (real_depth_mm.width() != w || real_depth_mm.height() != h || virtual_depth_mm.width() != w ||
      virtual_depth_mm.height() != h)
    throw std::invalid_argument("cvf_reference: colour and depth sizes differ");
  CvfTrace t;
  t.categories = categorise_reference(real_depth_mm, virtual_depth_mm, params.categorise);
  t.band = process_band_reference(t.categories, params.band_px);
  t.models = colour_histograms_reference(colour, t.categories, t.band, params.bins_per_channel);
  const auto min_samples = static_cast<std::uint32_t>(std::max(1, params.min_samples));
  t.colour_models_valid =
      t.models.infront_total() >= min_samples && t.models.behind_total() >= min_samples;

  t.cost = ImageF(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int bin = colour_bin(colour.at(x, y, 0), colour.at(x, y, 1), colour.at(x, y, 2),
                                 params.bins_per_channel);
      t.cost.at(x, y) =
          cvf_cost(static_cast<Category>(t.categories.at(x, y)), bin, t.models,
                   t.colour_models_valid, real_depth_mm.at(x, y), virtual_depth_mm.at(x, y));
    }

  const auto guide = guide_from_rgb8(colour);
  t.wide = guided_filter_reference(guide, t.cost, params.wide);
  t.mask = ImageF(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto c = static_cast<Category>(t.categories.at(x, y));
      // Known pixels keep their cost; process and off-object pixels take the thresholded
      // filter output, so the object's own outline does not read as an occlusion edge.
      t.mask.at(x, y) = c == Category::Infront   ? 1.0F
                        : c == Category::Behind  ? 0.0F
                        : t.wide.at(x, y) > 0.5F ? 1.0F
                                                 : 0.0F;
    }
  t.feather = guided_filter_reference(guide, t.mask, params.feather);
  t.alpha = visibility_from_cost(t.feather, virtual_depth_mm);
  return t;
}

}  // namespace probeless::occlusion
