#pragma once
// One RGB-D frame as the tracker sees it: grey intensity (0..255) and depth in metres (0 =
// unknown or outside the depth range) at each pyramid level, with the level's pinhole.
#include <vector>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"

namespace probeless::tracking {

struct DenseTrackerParams;

struct LevelCamera {
  int width = 0, height = 0;
  float fx = 0, fy = 0, cx = 0, cy = 0;
};

// The camera of pyramid level `level` (each level halves the previous by 2x2 averaging, so
// pixel centres move: c' = (c + 0.5) / 2 - 0.5).
LevelCamera level_camera(const PinholeIntrinsics& camera, int level);

struct FrameLevel {
  LevelCamera camera;
  ImageF intensity;
  ImageF depth_m;
};

// levels[i] is pyramid level finest_level + i.
struct FramePyramid {
  std::vector<FrameLevel> levels;
  FrameLevel distorted;  // scratch: the finest level before undistortion
};

// BT.601 luma of an 8-bit colour pixel (the grey the tracker aligns).
inline float luma(const std::uint8_t* rgb) {
  return 0.299f * rgb[0] + 0.587f * rgb[1] + 0.114f * rgb[2];
}

// Depth of a 2x2 block: the mean of the valid samples within 5% of the nearest one, so that
// a block across a depth edge takes the front surface instead of a point in mid-air.
float block_depth(const float* d, int n);

// Where each pixel of the undistorted finest level lies in the distorted one (x, y pairs,
// row-major); empty when the camera has no distortion. Outside the image: (-1, -1).
std::vector<float> undistortion_map(const PinholeCamera& camera, int finest_level);

// The CPU reference of the device's pyramid kernels. `undistort` from undistortion_map().
void build_pyramid_reference(const ImageRGB8& colour, const DepthImage& depth_mm,
                             const PinholeIntrinsics& camera, const DenseTrackerParams& params,
                             const std::vector<float>& undistort, FramePyramid& pyramid);

}  // namespace probeless::tracking
