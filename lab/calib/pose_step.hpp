// A small change of a pose, as the calibration's Levenberg-Marquardt solvers (the rig
// extrinsics and the Kannala-Brandt refinement) step their poses.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "core/pose.hpp"

namespace probeless::calib {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Rotation vector first, then translation; the rotation is applied on the left.
inline Pose perturbed(const Pose& p, const Vector6d& d) {
  Pose out;
  const double angle = d.head<3>().norm();
  const Eigen::Quaterniond dq =
      angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, d.head<3>() / angle))
                : Eigen::Quaterniond::Identity();
  out.rotation = (dq * p.rotation).normalized();
  out.translation = p.translation + d.tail<3>();
  return out;
}

}  // namespace probeless::calib
