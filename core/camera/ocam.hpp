#pragma once
// Scaramuzza's omnidirectional polynomial model as calibrated by OCamCalib (Scaramuzza et
// al. 2006), read from the toolbox's `calib_results.txt`.
//
// OCamCalib's own frame differs from ours: its sensor point is (row, column) and its z axis
// points out of the lens, away from the scene. This class converts at the boundary, so
// project()/unproject() speak the CameraModel convention (x = column, y = row, z forward);
// OCamParams keeps the numbers exactly as the toolbox writes them. See docs/camera-models.md.
#include <string_view>
#include <vector>

#include "core/camera/camera_model.hpp"

namespace probeless {

struct OCamParams {
  std::vector<double> pol;     // unprojection polynomial f(rho), ascending powers
  std::vector<double> invpol;  // projection polynomial rho(theta), ascending powers
  double xc = 0, yc = 0;       // centre, in OCamCalib's (row, column) convention
  double c = 1, d = 0, e = 0;  // affine coefficients
  int width = 0, height = 0;
  bool operator==(const OCamParams&) const = default;
};

class OCamCamera final : public CameraModel {
 public:
  explicit OCamCamera(OCamParams p);
  // Parses the text of an OCamCalib calib_results.txt. Throws ParseError naming the line.
  static OCamCamera parse(std::string_view text, std::string_view source_name = "calib_results");

  int width() const override { return p_.width; }
  int height() const override { return p_.height; }
  std::string kind() const override { return "ocam"; }
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p) const override;
  std::optional<Eigen::Vector3d> unproject(const Eigen::Vector2d& pixel) const override;
  std::unique_ptr<CameraModel> clone() const override;
  const OCamParams& params() const { return p_; }
  // The model's domain: pixels up to max_radius() from the centre (the farthest image corner,
  // where OCamCalib fits invpol) and rays up to max_angle() from the optical axis.
  double max_radius() const { return max_rho_; }
  double max_angle() const { return max_alpha_; }

 private:
  Eigen::Vector2d sensor_point(const Eigen::Vector2d& pixel) const;

  OCamParams p_;
  double max_rho_ = 0;    // pixels
  double max_alpha_ = 0;  // radians from the optical axis
};

}  // namespace probeless
