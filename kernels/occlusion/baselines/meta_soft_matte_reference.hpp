#pragma once
// CPU reference of the Meta-Quest-style soft occlusion (after the Depth API's
// "SOFT_OCCLUSION" shader path): per neighbourhood the min, max and mean of the valid depth;
// visibility of a depth d is vis(d) = clamp((d - v) / (k v), 0, 1) with a relative range
// k = 4 %; where vis(max) - vis(min) > 0.03 the result blends vis(min) and vis(max) by
// smoothstep(0.2, 0.8, t), t = (mean - min) / (max - min), else it is vis(mean). Pixels with
// no valid depth in the window are visible.
#include "core/image.hpp"

namespace probeless::occlusion {

struct MetaSoftParams {
  int radius = 2;                // 5x5 neighbourhood
  float relative_range = 0.04F;  // Meta: kRange = 1 / 1.04 - 1
  float blend_threshold = 0.03F;
  float foreground_level = 0.2F;
  float background_level = 0.8F;
};

ImageF meta_soft_matte_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                                 const MetaSoftParams& params = {});

}  // namespace probeless::occlusion
