#pragma once
// CPU reference of CVF's first step (thesis 3.3.1): every pixel of the virtual object is
// infront, behind or process by the depth test, infront/behind borders are eroded into
// process, and the colour-sampling band is marked around the process region.
#include "core/image.hpp"
#include "kernels/occlusion/common/cvf_params.hpp"

namespace probeless::occlusion {

// Raw depth test without erosion: off the object (virtual <= 0) Ignore; real depth unknown
// (0) or |real - virtual| <= tolerance Process; real < virtual Infront; else Behind.
Category raw_category(std::uint16_t real_mm, float virtual_mm, float tolerance_mm);
// The same with the tolerance at the pixel's virtual depth (depth_tolerance_mm()).
Category raw_category(std::uint16_t real_mm, float virtual_mm, const CategoriseParams& params);

// The depth test, then erosion of the infront/behind border: an infront pixel with a behind
// pixel in its (2e+1)^2 window, or a behind pixel with an infront one, becomes Process (the
// depth edge's position is uncertain by the sensor's lateral noise). Process pixels (holes,
// ties) do not erode their neighbours: eroding around every hole of a structured-light
// sensor turned a third of the object into "process" and tripled CVF's MSE on Middlebury
// (docs/occlusion.md, "Erosion"). Off-object pixels never erode. The window is square.
CategoryImage categorise_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                                   const CategoriseParams& params);

// 255 where a Process pixel lies within the (2b+1)^2 window, else 0.
ImageGray8 process_band_reference(const CategoryImage& categories, int band_px);

}  // namespace probeless::occlusion
