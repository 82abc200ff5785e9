#pragma once
// CPU reference of the ARCore-style soft occlusion: the depth is smoothed by a 5x5 mean over
// its valid samples, then the object fades linearly from hidden at real = (1 - w) virtual to
// visible at real = (1 + w) virtual, w = 1 % (after ARCore's depth-occlusion samples).
// Pixels with no valid depth in the window are visible (ARCore treats missing depth as far).
#include "core/image.hpp"

namespace probeless::occlusion {

struct SoftRampParams {
  int smoothing_radius = 2;           // 5x5
  float relative_half_width = 0.01F;  // +-1 % of the virtual depth
};

ImageF soft_ramp_matte_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                                 const SoftRampParams& params = {});

}  // namespace probeless::occlusion
