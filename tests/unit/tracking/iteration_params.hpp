#pragma once
// One Gauss-Newton iteration's parameters for comparing accumulations (reference, CPU path,
// device): a pose near a few frames' motion of fr1/rpy, so that residuals of every kind,
// inliers and outliers occur, the level's camera, and the rolling shutter's rotation.
#include <Eigen/Geometry>
#include <array>

#include "kernels/tracking/keyframe.hpp"
#include "kernels/tracking/normal_equations.hpp"

namespace probeless::testing {

inline tracking::IterationParams iteration_params_near_motion(const tracking::LevelCamera& c,
                                                              const std::array<float, 3>& readout) {
  const Eigen::Matrix3f R =
      Eigen::AngleAxisf(0.03f, Eigen::Vector3f(0.2f, 1.0f, 0.1f).normalized()).toRotationMatrix();
  tracking::IterationParams p{};
  for (int i = 0; i < 9; ++i) p.r[i] = R(i / 3, i % 3);
  p.t[0] = 0.01f, p.t[1] = -0.005f, p.t[2] = 0.002f;
  p.fx = c.fx, p.fy = c.fy, p.cx = c.cx, p.cy = c.cy;
  p.inv_gain = 1.0f / 1.05f, p.bias = -3.0f;
  p.inv_var_photo = 1.0f / 64.0f, p.inv_var_geo = 1.0f / 1e-4f, p.nu = 5.0f;
  p.photo_inlier = 20.0f, p.geo_inlier = 0.04f, p.min_depth = 0.15f;
  for (int i = 0; i < 3; ++i) p.readout_rotation[i] = readout[std::size_t(i)];
  return p;
}

}  // namespace probeless::testing
