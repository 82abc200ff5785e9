#pragma once
// The colour camera's undistortion as a remap built once (thesis 4.2.2 did the same for the
// fisheye): for each pixel of the ideal pinhole the renderer draws with (the same fx, fy, cx,
// cy, no distortion), the pixel of the real, Brown-distorted frame it shows. Applied at upload
// (kernels/undistort/undistort.hpp) to the colour (bilinear) and to the depth registered to it
// (nearest: a depth between a hand and the wall behind it is neither), so that the matte, the
// composite and the renderer agree pixel for pixel.
#include <optional>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"

namespace probeless {

struct UndistortMap {
  // Source pixels outside the model's domain hold this (x and y); a real source pixel, even
  // outside the frame, is far above it.
  static constexpr float kInvalid = -1.0e6F;
  Image<float, 2> source;  // per output pixel: (x, y) in the distorted frame
};

// nullopt when the camera has no distortion: nothing to remap, the upload stays a copy.
std::optional<UndistortMap> build_undistort_map(const PinholeCamera& camera);

}  // namespace probeless
