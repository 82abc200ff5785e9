#pragma once
// The plain C++ reference of matte_stabiliser.cl, operation for operation in float: what the
// tests compare the device with.
#include "core/image.hpp"
#include "kernels/occlusion/temporal/matte_stabiliser_params.hpp"

namespace probeless::occlusion {

struct StabiliserFrame {
  const ImageRGB8* colour = nullptr;
  const DepthImage* real_depth_mm = nullptr;  // 0 = unknown
  const ImageF* virtual_depth_mm = nullptr;   // 0 = no object
};

// The current matte `alpha` blended with `prev_alpha` (the previous frame's stabilised matte)
// re-projected with `motion`. All images one size; throws std::invalid_argument otherwise.
ImageF stabilise_matte_reference(const ImageF& alpha, const StabiliserFrame& current,
                                 const ImageF& prev_alpha, const StabiliserFrame& previous,
                                 const StabiliserMotion& motion, const StabiliserParams& params);

}  // namespace probeless::occlusion
