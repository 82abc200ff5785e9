#pragma once
// Pinhole camera with Brown-Conrady distortion (OpenCV's k1 k2 p1 p2 k3 order), the model of
// RGB-D colour cameras. With all coefficients zero it is the ideal pinhole the renderer uses.
#include <limits>

#include "core/camera/camera_model.hpp"

namespace probeless {

struct PinholeIntrinsics {
  int width = 640;
  int height = 480;
  double fx = 525.0, fy = 525.0;  // TUM / Kinect v1 class defaults
  double cx = 319.5, cy = 239.5;
  bool operator==(const PinholeIntrinsics&) const = default;
};

struct BrownDistortion {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  bool is_zero() const { return k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0; }
  bool operator==(const BrownDistortion&) const = default;
};

class PinholeCamera final : public CameraModel {
 public:
  PinholeCamera() = default;
  // Directions whose normalised radius lies beyond the point where the radial polynomial
  // folds back (strong negative k) are not seen: project() returns nullopt for them.
  explicit PinholeCamera(PinholeIntrinsics k, BrownDistortion d = {});

  int width() const override { return k_.width; }
  int height() const override { return k_.height; }
  std::string kind() const override { return "pinhole"; }
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p) const override;
  // Undistortion by fixed-point iteration (converges for the moderate distortion of RGB-D
  // colour cameras).
  std::optional<Eigen::Vector3d> unproject(const Eigen::Vector2d& pixel) const override;
  std::unique_ptr<CameraModel> clone() const override;

  const PinholeIntrinsics& intrinsics() const { return k_; }
  const BrownDistortion& distortion() const { return d_; }
  // 3x3 K matrix.
  Eigen::Matrix3d matrix() const;

 private:
  PinholeIntrinsics k_;
  BrownDistortion d_;
  double max_radius_ = std::numeric_limits<double>::infinity();  // normalised radius where the
                                                                 // distortion stops increasing
};

}  // namespace probeless
