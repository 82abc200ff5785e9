#pragma once
// Equidistant fisheye with the Kannala-Brandt polynomial, exactly OpenCV's cv::fisheye model:
// theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
// u = fx * theta_d * x/r + cx (r = |(x, y)|, theta = atan2(r, z)). With k = 0 it is the ideal
// equidistant projection the synthetic rig's fisheye uses.
#include <array>

#include "core/camera/camera_model.hpp"

namespace probeless {

struct KannalaBrandtParams {
  int width = 1024;
  int height = 1024;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<double, 4> k{0, 0, 0, 0};
  double max_theta = 1.65;  // radians from the axis the model is valid to (about 189 deg FOV)
  bool operator==(const KannalaBrandtParams&) const = default;
};

// The model's theta_d for an angle theta from the axis (radians): the polynomial above. What
// project() scales by, and, at max_theta, the radius of the image circle in focal lengths.
double kannala_brandt_distorted_angle(const std::array<double, 4>& k, double theta);

class KannalaBrandtCamera final : public CameraModel {
 public:
  explicit KannalaBrandtCamera(KannalaBrandtParams p);
  // An ideal equidistant fisheye of `size` x `size` pixels whose image circle (diameter
  // `size`) spans `fov_deg` degrees.
  static KannalaBrandtCamera equidistant(int size, double fov_deg);

  int width() const override { return p_.width; }
  int height() const override { return p_.height; }
  std::string kind() const override { return "kannala_brandt"; }
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p) const override;
  std::optional<Eigen::Vector3d> unproject(const Eigen::Vector2d& pixel) const override;
  std::unique_ptr<CameraModel> clone() const override;
  const KannalaBrandtParams& params() const { return p_; }

 private:
  KannalaBrandtParams p_;
};

}  // namespace probeless
