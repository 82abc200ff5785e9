#pragma once
// Images of a board seen through any of core's camera models, rendered by ray casting (2 x 2
// samples a pixel): the synthetic views of the calibration's end-to-end test.
#include "core/camera/camera_model.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"
#include "lab/calib/board_detector.hpp"

namespace probeless::calib::testing {

// `print` is board_image(spec, pixels_per_square); `origin_m` its offset (0 for ChArUco).
inline ImageGray8 render_board(const CameraModel& camera, const Pose& T_camera_board,
                               const ImageGray8& print, double square_m, int pixels_per_square,
                               double origin_m) {
  ImageGray8 out(camera.width(), camera.height());
  const Pose T_board_camera = T_camera_board.inverse();
  const double scale = pixels_per_square / square_m;  // print pixels per metre
  const double margin = pixels_per_square;            // white paper around the print
  for (int v = 0; v < out.height(); ++v)
    for (int u = 0; u < out.width(); ++u) {
      int sum = 0;
      for (double dv : {-0.25, 0.25})
        for (double du : {-0.25, 0.25}) {
          int value = 90;  // the room behind the board
          if (const auto ray = camera.unproject({u + du, v + dv})) {
            const Eigen::Vector3d o = T_board_camera.translation;
            const Eigen::Vector3d d = T_board_camera.rotation * *ray;
            const double t = -o.z() / d.z();
            if (t > 0 && std::isfinite(t)) {
              const Eigen::Vector3d p = o + t * d;
              const double x = (p.x() + origin_m) * scale, y = (p.y() + origin_m) * scale;
              if (x >= 0 && y >= 0 && x < print.width() && y < print.height())
                value = print.at(static_cast<int>(x), static_cast<int>(y));
              else if (x > -margin && y > -margin && x < print.width() + margin &&
                       y < print.height() + margin)
                value = 235;
            }
          }
          sum += value;
        }
      out.at(u, v) = static_cast<std::uint8_t>(sum / 4);
    }
  return out;
}

}  // namespace probeless::calib::testing
