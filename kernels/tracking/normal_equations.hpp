#pragma once
// One Gauss-Newton iteration's sums over the keyframe points: the 6x6 normal equations of the
// photometric and point-to-plane residuals with Student-t weights, plus what re-estimates the
// t-scales, the brightness model and the loss test. The device kernel (tracking.cl,
// accumulate_normal_equations) computes the same sums per work-group.
#include <array>
#include <vector>

#include "kernels/tracking/keyframe.hpp"

namespace probeless::tracking {

// Per iteration, passed by value to the kernel: 24 floats, the order tracking.cl reads.
struct IterationParams {
  float r[9];            // R_current_keyframe, row-major
  float t[3];            // t_current_keyframe
  float fx, fy, cx, cy;  // the level's camera
  float inv_gain, bias;  // brightness: I_kf ~ (I_cur - bias) * inv_gain
  float inv_var_photo;   // 1 / sigma^2 of the photometric t-distribution
  float inv_var_geo;     // 1 / sigma^2 of the point-to-plane t-distribution
  float nu;              // t-distribution degrees of freedom
  float photo_inlier;    // |r| bounds of an inlier
  float geo_inlier;
  float min_depth;  // points nearer than this after the warp are not visible
  // Rolling shutter: the current frame's rotation (rad, its camera axes) from the top row's
  // exposure to the bottom row's; zero for a global shutter (docs/tracking.md).
  float readout_rotation[3];
  float pad;
};
static_assert(sizeof(IterationParams) == 28 * sizeof(float));

// Indices into the sums.
enum Sum : int {
  kH = 0,            // 21: upper triangle of H, row-major
  kG = 21,           // 6: J^T W r
  kPhotoCount = 27,  // photometric residuals
  kPhotoWeightedSq,  // sum w_t r^2 (the t-scale's fixed point, Kerl et al. eq. 10)
  kPhotoSq,          // sum r^2
  kGeoCount,
  kGeoWeightedSq,
  kGeoSq,
  kVisible,  // points inside the frame
  kInliers,  // visible points whose residuals are within the inlier bounds
  kAffineW,  // sum w, w x, w y, w x^2, w y^2 (x keyframe, y current intensity)
  kAffineX,
  kAffineY,
  kAffineXX,
  kAffineYY,
  kSumCount  // 40
};
static_assert(kSumCount == 40);

using NormalSums = std::array<double, kSumCount>;

// The CPU reference: per point in float as the device, summed in double.
NormalSums accumulate_reference(const std::vector<TrackPoint>& points, const FrameLevel& frame,
                                const IterationParams& params);

// The CPU path the tracker runs (normal_equations_cpu.cpp): the same sums, four points at a
// time in vector registers; equal to the reference to float rounding (the tests' bound).
NormalSums accumulate_cpu(const std::vector<TrackPoint>& points, const FrameLevel& frame,
                          const IterationParams& params);

}  // namespace probeless::tracking
