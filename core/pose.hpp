#pragma once
// Rigid poses. Convention used everywhere: a Pose named T_a_b maps points from frame b to
// frame a (p_a = T_a_b * p_b). A rig pose is T_world_rig. Camera frames follow OpenCV:
// x right, y down, z forward. The world frame is right-handed with z up (gravity along -z).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "core/time.hpp"

namespace probeless {

struct Pose {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  static Pose identity() { return {}; }
  static Pose from_matrix(const Eigen::Matrix4d& m);
  Eigen::Matrix4d matrix() const;

  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return rotation * p + translation; }
  Pose operator*(const Pose& other) const;
  Pose inverse() const;
};

// Linear interpolation of translation and slerp of rotation, t in [0,1] (not clamped).
Pose interpolate(const Pose& a, const Pose& b, double t);

// A time-stamped sequence of poses (TUM trajectory files map onto this one to one).
class Trajectory {
 public:
  struct Sample {
    TimestampNs timestamp_ns;
    Pose pose;
  };
  // Samples must arrive in increasing time; throws std::invalid_argument otherwise.
  void append(TimestampNs t, const Pose& pose);
  // Interpolated pose at t; nullopt outside [front, back].
  std::optional<Pose> at(TimestampNs t) const;
  const std::vector<Sample>& samples() const { return samples_; }
  bool empty() const { return samples_.empty(); }

 private:
  std::vector<Sample> samples_;
};

}  // namespace probeless
