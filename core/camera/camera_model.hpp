#pragma once
// The seam between geometry and pixels. Pixel coordinates follow OpenCV: (0,0) is the centre
// of the top-left pixel, x right, y down. Camera frame: x right, y down, z forward (optical
// axis). Rays returned by unproject() are unit length.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>

namespace probeless {

class CameraModel {
 public:
  virtual ~CameraModel() = default;

  virtual int width() const = 0;
  virtual int height() const = 0;
  // Short name for logs and config ("pinhole", "kannala_brandt", "ocam").
  virtual std::string kind() const = 0;

  // A point or direction in the camera frame -> pixel. nullopt when the model cannot see it
  // (behind a pinhole camera, beyond a fisheye's field of view). The pixel may lie outside
  // the image; callers that need it inside check with in_image().
  virtual std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p) const = 0;
  // Pixel -> unit ray in the camera frame; nullopt outside the model's valid domain.
  virtual std::optional<Eigen::Vector3d> unproject(const Eigen::Vector2d& pixel) const = 0;

  virtual std::unique_ptr<CameraModel> clone() const = 0;

  bool in_image(const Eigen::Vector2d& px) const {
    return px.x() > -0.5 && px.y() > -0.5 && px.x() < width() - 0.5 && px.y() < height() - 0.5;
  }
};

}  // namespace probeless
