#pragma once
// The exponential map of SE(3): xi = (v, w), translation first, as the Jacobians of
// keyframe.cpp are ordered.
#include <Eigen/Core>

#include "core/pose.hpp"

namespace probeless::tracking {

using Vector6d = Eigen::Matrix<double, 6, 1>;

inline Pose se3_exp(const Vector6d& xi) {
  const Eigen::Vector3d v = xi.head<3>(), w = xi.tail<3>();
  const double theta = w.norm();
  Eigen::Matrix3d W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  double a, b;  // (1 - cos)/theta^2, (theta - sin)/theta^3
  if (theta < 1e-6) {
    a = 0.5 - theta * theta / 24.0;
    b = 1.0 / 6.0 - theta * theta / 120.0;
  } else {
    a = (1.0 - std::cos(theta)) / (theta * theta);
    b = (theta - std::sin(theta)) / (theta * theta * theta);
  }
  const Eigen::Matrix3d V = Eigen::Matrix3d::Identity() + a * W + b * W * W;
  Pose p;
  const Eigen::Vector3d axis = theta > 0 ? Eigen::Vector3d(w / theta) : Eigen::Vector3d::UnitX();
  p.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(theta, axis));
  p.translation = V * v;
  return p;
}

}  // namespace probeless::tracking
