#pragma once
// CPU reference of the "Bilateral" baseline (thesis 3.4): a joint bilateral filter, guided by
// the colour frame, that fills each process pixel from the infront (0) and behind (1) pixels
// of its window only. Known pixels keep their value; a process pixel with no known
// neighbour is 0.5.
#include "core/image.hpp"
#include "kernels/occlusion/common/cvf_params.hpp"

namespace probeless::occlusion {

struct BilateralMatteParams {
  CategoriseParams categorise;
  int radius = 6;  // as CVF's wide filter
  float sigma_space_px = 3.0F;
  float sigma_colour = 0.1F;  // Euclidean RGB distance, components in [0, 1]
};

ImageF bilateral_matte_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                                 const ImageF& virtual_depth_mm,
                                 const BilateralMatteParams& params = {});

}  // namespace probeless::occlusion
