#pragma once
// The fisheye as the envmap update sees it, whatever its model (thesis 4.2.2: the fisheye was
// undistorted through a lookup table built once). The table is indexed by the ideal
// equidistant projection of a direction in the fisheye's frame, g = centre + scale theta
// (x, y) / r (theta = angle from the optical axis, r = |(x, y)|), and holds the pixel of the
// real camera that direction lands on: the update kernel computes g (the arithmetic of a
// Kannala-Brandt model with k = 0), interpolates the table bilinearly and samples the frame
// there, so it does not care which core/camera model filled the table.
//
// Why the table is in the fisheye's frame and not one entry per keyframe texel: the texel ->
// pixel map changes with every frame's pose (and with the parallax offset), so a per-texel
// table would be rebuilt and uploaded every frame; this one depends on the camera only and is
// built once per estimator. For an equidistant fisheye (the sim's) the table is linear in g,
// so bilinear interpolation reproduces the analytic projection to float rounding; for a
// distorted Kannala-Brandt, OCamCalib or Brown lens the map is smooth and two-pixel cells
// leave under 0.01 px (tests/kernels/envmap/fisheye_lut_test.cpp).
#include <memory>
#include <string>

#include "core/camera/camera_model.hpp"
#include "core/image.hpp"

namespace probeless::envmap {

struct FisheyeLut {
  // Cells holding this in x (and y) are directions the model cannot see: a footprint touching
  // one is not sampled. Real pixels, even outside the image, are far above it.
  static constexpr float kInvalid = -1.0e6F;

  int size = 0;      // the table is size x size cells
  float centre = 0;  // cell coordinate of the optical axis (both axes)
  float scale = 0;   // cells per radian of theta
  // The widest angle from the axis the model projects (Kannala-Brandt: its max_theta): the
  // kernel samples nothing beyond. Cells up to a few beyond hold the model extrapolated
  // along the radius, so that directions just inside keep four valid corners.
  float max_theta = 0;
  Image<float, 2> pixel;                  // (u, v) per cell, or kInvalid
  int image_width = 0, image_height = 0;  // the camera's frame size
  std::string model;                      // CameraModel::kind(), for errors
};

// Builds the table from any camera model. cell_px: about how many fisheye pixels one cell
// spans near the axis (2 keeps a 1024 px fisheye's table at ~2 MB). Throws
// std::invalid_argument for a model whose axis does not project, or a bad cell_px.
std::shared_ptr<const FisheyeLut> build_fisheye_lut(const CameraModel& camera,
                                                    float cell_px = 2.0F);

}  // namespace probeless::envmap
