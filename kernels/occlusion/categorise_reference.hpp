#pragma once
// CPU reference of CVF's first step (thesis 3.3.1): every pixel of the virtual object is
// infront, behind or process by the depth test, infront/behind borders are eroded into
// process, and the colour-sampling band is marked around the process region.
#include "core/image.hpp"
#include "kernels/occlusion/cvf_params.hpp"

namespace probeless::occlusion {

// Raw depth test without erosion: off the object (virtual <= 0) Ignore; real depth unknown
// (0) or |real - virtual| <= tolerance Process; real < virtual Infront; else Behind.
Category raw_category(std::uint16_t real_mm, float virtual_mm, float tolerance_mm);

// The depth test, then erosion: an infront (behind) pixel with an on-object pixel of another
// raw category in its (2e+1)^2 window becomes Process. Off-object pixels never erode (the
// object's own outline is no depth edge). The window is square (Chebyshev distance).
CategoryImage categorise_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                                   const CategoriseParams& params);

// 255 where a Process pixel lies within the (2b+1)^2 window, else 0.
ImageGray8 process_band_reference(const CategoryImage& categories, int band_px);

}  // namespace probeless::occlusion
