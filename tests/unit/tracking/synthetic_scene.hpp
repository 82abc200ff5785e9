#pragma once
// A textured room corner (back wall, floor, left wall) rendered into colour + depth from any
// camera pose, for the tracker's tests: exact depth, no noise, a smooth texture with
// gradients at every pyramid level.
#include <cmath>
#include <cstdint>
#include <functional>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"

namespace probeless::testing {

struct RenderedFrame {
  ImageRGB8 colour;
  DepthImage depth_mm;
};

// Grey texture in [0, 255] over a plane's two coordinates (metres); `pattern` picks another.
inline double room_texture(double u, double v, int pattern) {
  if (pattern == 0)
    return 128 + 50 * std::sin(11 * u) * std::cos(9 * v) + 35 * std::sin(27 * u + 17 * v) +
           20 * std::cos(41 * v - 7 * u);
  return 128 + 60 * std::cos(31 * u - 5 * v) * std::sin(3 * v) + 40 * std::sin(53 * v + 29 * u);
}

// T_world_camera: OpenCV axes (x right, y down, z forward); the room's back wall at z = 2.2,
// floor at y = 0.7, left wall at x = -1.0 (world = the first camera).
// `row_pose(y)`: the camera's pose when row y was exposed (a rolling shutter); render_room
// below is the global shutter's case.
template <class RowPose>
RenderedFrame render_room_rows(const PinholeIntrinsics& k, RowPose row_pose, int pattern = 0) {
  RenderedFrame f{ImageRGB8(k.width, k.height), DepthImage(k.width, k.height)};
  for (int y = 0; y < k.height; ++y) {
    const Pose T_world_camera = row_pose(y);
    const Eigen::Matrix3d R = T_world_camera.rotation.toRotationMatrix();
    const Eigen::Vector3d c = T_world_camera.translation;
    for (int x = 0; x < k.width; ++x) {
      const Eigen::Vector3d ray((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0);
      const Eigen::Vector3d d = R * ray;
      double best = 1e9, grey = 0;
      auto hit = [&](int axis, double at, int ua, int va) {
        if (std::abs(d[axis]) < 1e-9) return;
        const double t = (at - c[axis]) / d[axis];
        if (t <= 0 || t >= best) return;
        const Eigen::Vector3d p = c + t * d;
        best = t;
        grey = room_texture(p[ua], p[va], pattern);
      };
      hit(2, 2.2, 0, 1);   // back wall
      hit(1, 0.7, 0, 2);   // floor
      hit(0, -1.0, 2, 1);  // left wall
      if (best >= 1e9) continue;
      const double z = best;  // ray has z = 1 in the camera: t is the depth
      const auto g = std::uint8_t(std::clamp(std::lround(grey), 0L, 255L));
      f.colour.at(x, y, 0) = f.colour.at(x, y, 1) = f.colour.at(x, y, 2) = g;
      f.depth_mm.at(x, y) = std::uint16_t(std::lround(z * 1000.0));
    }
  }
  return f;
}

inline RenderedFrame render_room(const PinholeIntrinsics& k, const Pose& T_world_camera,
                                 int pattern = 0) {
  return render_room_rows(
      k, [&](int) { return T_world_camera; }, pattern);
}

inline Pose pose_from(double tx, double ty, double tz, double rx_deg, double ry_deg,
                      double rz_deg) {
  Pose p;
  const double r = M_PI / 180.0;
  p.rotation = Eigen::AngleAxisd(rx_deg * r, Eigen::Vector3d::UnitX()) *
               Eigen::AngleAxisd(ry_deg * r, Eigen::Vector3d::UnitY()) *
               Eigen::AngleAxisd(rz_deg * r, Eigen::Vector3d::UnitZ());
  p.translation = {tx, ty, tz};
  return p;
}

inline double rotation_error_deg(const Pose& a, const Pose& b) {
  return a.rotation.angularDistance(b.rotation) * 180.0 / M_PI;
}

}  // namespace probeless::testing
