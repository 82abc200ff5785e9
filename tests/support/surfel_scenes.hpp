#pragma once
// Ray-cast noise-free views for the surfel map's tests (the CPU reference's in tests/unit/fusion
// and the device's in tests/kernels/fusion run the same scenes): a floor z = 0 under a camera
// looking straight down, and a box standing on it.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"
#include "kernels/fusion/surfel_map_params.hpp"

namespace probeless::testing {

struct AlignedBox {
  Eigen::Vector3d lo, hi;
  bool contains(const Eigen::Vector3f& p, double margin) const {
    return (p.cast<double>().array() >= lo.array() - margin).all() &&
           (p.cast<double>().array() <= hi.array() + margin).all();
  }
};

struct View {
  PinholeIntrinsics k;
  DepthImage depth;
  ImageRGB8 colour;
  Pose T_world_camera;
};

// Camera x = world x, y = world -y, z = world -z: looking down from `height` over (x, y),
// turned by `yaw` about the vertical.
inline Pose looking_down(double x, double y, double height, double yaw = 0) {
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  Pose T;
  T.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * r);
  T.translation = {x, y, height};
  return T;
}

// The floor z = 0 (grey 128) and, if given, a box on it (grey 200), ray cast per pixel.
inline View render(const Pose& T_world_camera, const std::optional<AlignedBox>& box,
                   int width = 640, int height = 480) {
  View v;
  v.k.width = width;
  v.k.height = height;
  v.k.cx = (width - 1) / 2.0;
  v.k.cy = (height - 1) / 2.0;
  v.depth = DepthImage(width, height);
  v.colour = ImageRGB8(width, height);
  v.T_world_camera = T_world_camera;
  const Eigen::Matrix3d R = T_world_camera.rotation.toRotationMatrix();
  const Eigen::Vector3d o = T_world_camera.translation;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector3d ray_c((x - v.k.cx) / v.k.fx, (y - v.k.cy) / v.k.fy, 1.0);
      const Eigen::Vector3d d = R * ray_c;  // t along d is camera z, as ray_c.z = 1
      double t = d.z() < 0 ? -o.z() / d.z() : -1;
      std::uint8_t grey = 128;
      if (box) {  // slab test
        double t0 = 0, t1 = 1e9;
        for (int a = 0; a < 3; ++a) {
          const double ta = (box->lo[a] - o[a]) / d[a], tb = (box->hi[a] - o[a]) / d[a];
          t0 = std::max(t0, std::min(ta, tb));
          t1 = std::min(t1, std::max(ta, tb));
        }
        if (t0 <= t1 && t0 > 0 && (t < 0 || t0 < t)) {
          t = t0;
          grey = 200;
        }
      }
      if (t <= 0) continue;
      v.depth.at(x, y) = static_cast<std::uint16_t>(std::lround(t * 1000));
      for (int c = 0; c < 3; ++c) v.colour.at(x, y, c) = grey;
    }
  return v;
}

// A surfel `offset` from `centre`, facing it: what an environment rendered at `centre` sees
// face-on.
inline fusion::Surfel facing_surfel(const Eigen::Vector3f& centre, const Eigen::Vector3f& offset,
                                    float radius, const std::array<float, 3>& radiance) {
  fusion::Surfel s;
  s.position = centre + offset;
  s.normal = -offset.normalized();
  s.radius = radius;
  s.radiance = radiance;
  return s;
}

// What integrate() of either map (the reference or the device's) says of a frame: the
// std::invalid_argument's message, or "no throw".
template <typename Map>
std::string integrate_error(Map& map, const DepthImage& depth, const ImageRGB8& colour,
                            std::array<float, 3> radiance_per_unit, const PinholeIntrinsics& k,
                            const Pose& T_world_camera) {
  try {
    map.integrate(depth, colour, radiance_per_unit, k, T_world_camera, 0);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "no throw";
}

}  // namespace probeless::testing
