#pragma once
// Plain C++ of undistort.cl, for the kernel tests.
#include "core/image.hpp"
#include "kernels/undistort/undistort_map.hpp"

namespace probeless {

ImageRGB8 undistort_colour_reference(const ImageRGB8& in, const UndistortMap& map);
DepthImage undistort_depth_reference(const DepthImage& in, const UndistortMap& map);

}  // namespace probeless
