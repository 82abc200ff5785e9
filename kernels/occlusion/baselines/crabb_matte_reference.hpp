#pragma once
// CPU reference of the "Crabb et al." baseline (Crabb, Tracey, Puranik & Davis, CVPR
// workshops 2008; thesis 3.4): one depth threshold at the virtual object's mean depth. The
// object is hidden where the real depth is known and nearer than that mean; unknown depth
// counts as background, as in Crabb et al.'s segmentation.
#include "core/image.hpp"

namespace probeless::occlusion {

// Mean of virtual_depth_mm over the object's pixels (virtual > 0); 0 when there are none.
double mean_virtual_depth(const ImageF& virtual_depth_mm);

ImageF crabb_matte_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm);

}  // namespace probeless::occlusion
