#include "core/pose.hpp"

#include <algorithm>
#include <stdexcept>

namespace probeless {

Pose Pose::from_matrix(const Eigen::Matrix4d& m) {
  Pose p;
  p.rotation = Eigen::Quaterniond(Eigen::Matrix3d(m.topLeftCorner<3, 3>())).normalized();
  p.translation = m.topRightCorner<3, 1>();
  return p;
}

Eigen::Matrix4d Pose::matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rotation.toRotationMatrix();
  m.topRightCorner<3, 1>() = translation;
  return m;
}

Pose Pose::operator*(const Pose& other) const {
  Pose p;
  p.rotation = (rotation * other.rotation).normalized();
  p.translation = rotation * other.translation + translation;
  return p;
}

Pose Pose::inverse() const {
  Pose p;
  p.rotation = rotation.conjugate();
  p.translation = -(p.rotation * translation);
  return p;
}

Pose interpolate(const Pose& a, const Pose& b, double t) {
  Pose p;
  p.translation = (1.0 - t) * a.translation + t * b.translation;
  // Eigen's slerp takes the shorter arc (it flips the sign of b when the dot product is < 0).
  p.rotation = a.rotation.slerp(t, b.rotation).normalized();
  return p;
}

void Trajectory::append(TimestampNs t, const Pose& pose) {
  if (!samples_.empty() && t <= samples_.back().timestamp_ns)
    throw std::invalid_argument("Trajectory: timestamps must increase");
  samples_.push_back({t, pose});
}

std::optional<Pose> Trajectory::at(TimestampNs t) const {
  if (samples_.empty() || t < samples_.front().timestamp_ns || t > samples_.back().timestamp_ns)
    return std::nullopt;
  auto it = std::lower_bound(samples_.begin(), samples_.end(), t,
                             [](const Sample& s, TimestampNs v) { return s.timestamp_ns < v; });
  if (it->timestamp_ns == t) return it->pose;
  const Sample& b = *it;
  const Sample& a = *(it - 1);
  double u = static_cast<double>(t - a.timestamp_ns) /
             static_cast<double>(b.timestamp_ns - a.timestamp_ns);
  return interpolate(a.pose, b.pose, u);
}

}  // namespace probeless
