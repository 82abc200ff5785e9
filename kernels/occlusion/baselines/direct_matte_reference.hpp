#pragma once
// CPU reference of the Direct matte (kernels/occlusion/baselines/direct_matte.cl), plain loops.
#include "core/image.hpp"
#include "kernels/occlusion/baselines/direct_matte.hpp"

namespace probeless::occlusion {

// 0 off the object (virtual depth not > 0); on it, `unknown` decides real depth 0; else
// 1 where real >= virtual (the real surface is at or behind the object), 0 where nearer.
float direct_alpha(std::uint16_t real_mm, float virtual_mm, UnknownDepth unknown);

ImageF direct_matte_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                              UnknownDepth unknown);

}  // namespace probeless::occlusion
