#include "kernels/envmap/envmap_types.hpp"

#include <cmath>
#include <stdexcept>

namespace probeless::envmap {

Cubemap to_cubemap(const ImageRGBAF& texels) {
  const int n = face_size_of(texels);
  Cubemap cube(n);
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        for (int c = 0; c < 3; ++c) cube.faces[f].at(x, y, c) = texels.at(x, f * n + y, c);
  return cube;
}

const char* to_string(UpdateRule rule) {
  return rule == UpdateRule::Kalman ? "kalman" : "best_score";
}

Eigen::Vector3f cube_face_direction(int face, float u, float v) {
  const float sc = 2.0F * u - 1.0F, tc = 2.0F * v - 1.0F;
  switch (face) {
    case 0:
      return {1.0F, -tc, -sc};
    case 1:
      return {-1.0F, -tc, sc};
    case 2:
      return {sc, 1.0F, tc};
    case 3:
      return {sc, -1.0F, -tc};
    case 4:
      return {sc, -tc, 1.0F};
    default:
      return {-sc, -tc, -1.0F};
  }
}

void validate(const RoomBox& room) {
  if (!(room.lo.allFinite() && room.hi.allFinite() && (room.lo.array() < room.hi.array()).all()))
    throw std::invalid_argument("room box: lo must be below hi in x, y and z (finite metres)");
}

bool inside(const RoomBox& room, const Eigen::Vector3d& p) {
  return (p.array() > room.lo.array()).all() && (p.array() < room.hi.array()).all();
}

ParallaxConstants parallax_constants(const FisheyeView& view) {
  ParallaxConstants c;
  if (!view.room || !inside(*view.room, view.keyframe_position)) return c;
  c.enabled = true;
  c.lo = (view.room->lo - view.keyframe_position).cast<float>();
  c.hi = (view.room->hi - view.keyframe_position).cast<float>();
  c.offset = (view.keyframe_position - view.position).cast<float>();
  return c;
}

float box_exit(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const Eigen::Vector3f& d) {
  float t[3];
  for (int i = 0; i < 3; ++i) {
    const float a = lo[i] / d[i];  // separate statements, as the kernel's vector operations
    const float b = hi[i] / d[i];
    t[i] = std::fmax(a, b);
  }
  return std::fmin(t[0], std::fmin(t[1], t[2]));
}

Eigen::Vector3f parallax_direction(const ParallaxConstants& p, const Eigen::Vector3f& d) {
  if (!p.enabled) return d;
  const float t = box_exit(p.lo, p.hi, d);
  Eigen::Vector3f w;
  for (int i = 0; i < 3; ++i) {
    const float td = t * d[i];  // no fused multiply-add: the kernel's contraction is off
    w[i] = p.offset[i] + td;
  }
  return w;
}

CubeCoord cube_coord_of(const Eigen::Vector3f& d) {
  const float ax = std::abs(d.x()), ay = std::abs(d.y()), az = std::abs(d.z());
  CubeCoord t;
  float sc, tc, ma;
  if (ax >= ay && ax >= az) {
    ma = ax;
    t.face = d.x() > 0.0F ? 0 : 1;
    sc = d.x() > 0.0F ? -d.z() : d.z();
    tc = -d.y();
  } else if (ay >= az) {
    ma = ay;
    t.face = d.y() > 0.0F ? 2 : 3;
    sc = d.x();
    tc = d.y() > 0.0F ? d.z() : -d.z();
  } else {
    ma = az;
    t.face = d.z() > 0.0F ? 4 : 5;
    sc = d.z() > 0.0F ? d.x() : -d.x();
    tc = -d.y();
  }
  t.u = 0.5F * (sc / ma + 1.0F);
  t.v = 0.5F * (tc / ma + 1.0F);
  return t;
}

}  // namespace probeless::envmap
