#pragma once
// CPU reference of the "Guided" baseline (thesis 3.4): one guided filter over the category
// matte (behind 1, process 0.5, infront and off-object 0), no threshold.
#include "core/image.hpp"
#include "kernels/occlusion/common/cvf_params.hpp"

namespace probeless::occlusion {

struct GuidedMatteParams {
  CategoriseParams categorise;
  GuidedFilterParams filter{6, 0.0025F, 1};  // CVF's wide filter
};

float guided_matte_value(Category c);

ImageF guided_matte_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                              const ImageF& virtual_depth_mm, const GuidedMatteParams& params = {});

}  // namespace probeless::occlusion
