#pragma once
// CPU reference of the Direct matte (kernels/occlusion/baselines/direct_matte.cl), plain loops.
#include "core/image.hpp"
#include "kernels/occlusion/baselines/direct_matte.hpp"

namespace probeless::occlusion {

// 0 off the object (virtual depth not > 0); on it, `unknown` decides real depth 0; else
// 1 where real >= virtual - tolerance (the real surface is at or behind the object, within the
// sensor's noise: a real surface the sensor cannot tell from the object's does not hide it,
// issue #19 item 6), 0 where nearer.
float direct_alpha(std::uint16_t real_mm, float virtual_mm, UnknownDepth unknown,
                   float tolerance_mm = 0.0F);

// The tolerance at each pixel's virtual depth is depth_tolerance_mm(tolerance, v).
ImageF direct_matte_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                              UnknownDepth unknown, const CategoriseParams& tolerance = {});

}  // namespace probeless::occlusion
