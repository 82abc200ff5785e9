#include "core/cubemap.hpp"

#include <algorithm>
#include <cmath>

namespace probeless {

// OpenGL cube map selection (OpenGL ES 3.0 spec, table 3.21): major axis, then
// s = (sc / |ma| + 1) / 2, t = (tc / |ma| + 1) / 2 with t growing downwards in the face image.
CubeTexel cube_texel_from_direction(const Eigen::Vector3d& d) {
  const double ax = std::abs(d.x()), ay = std::abs(d.y()), az = std::abs(d.z());
  CubeFace face;
  double sc, tc, ma;
  if (ax >= ay && ax >= az) {
    ma = ax;
    if (d.x() > 0) { face = CubeFace::PosX; sc = -d.z(); tc = -d.y(); }
    else { face = CubeFace::NegX; sc = d.z(); tc = -d.y(); }
  } else if (ay >= az) {
    ma = ay;
    if (d.y() > 0) { face = CubeFace::PosY; sc = d.x(); tc = d.z(); }
    else { face = CubeFace::NegY; sc = d.x(); tc = -d.z(); }
  } else {
    ma = az;
    if (d.z() > 0) { face = CubeFace::PosZ; sc = d.x(); tc = -d.y(); }
    else { face = CubeFace::NegZ; sc = -d.x(); tc = -d.y(); }
  }
  return {face, 0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0)};
}

Eigen::Vector3d cube_direction(CubeFace face, double u, double v) {
  const double sc = 2.0 * u - 1.0, tc = 2.0 * v - 1.0;
  Eigen::Vector3d d;
  switch (face) {
    case CubeFace::PosX: d = {1.0, -tc, -sc}; break;
    case CubeFace::NegX: d = {-1.0, -tc, sc}; break;
    case CubeFace::PosY: d = {sc, 1.0, tc}; break;
    case CubeFace::NegY: d = {sc, -1.0, -tc}; break;
    case CubeFace::PosZ: d = {sc, -tc, 1.0}; break;
    case CubeFace::NegZ: d = {-sc, -tc, -1.0}; break;
  }
  return d.normalized();
}

namespace {
// Solid angle of the face region from the centre (0,0) to (x, y), in face coordinates [-1,1].
double area_element(double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1)); }
}  // namespace

double cube_texel_solid_angle(int x, int y, int n) {
  const double inv = 1.0 / n;
  const double x0 = 2.0 * x * inv - 1.0, x1 = 2.0 * (x + 1) * inv - 1.0;
  const double y0 = 2.0 * y * inv - 1.0, y1 = 2.0 * (y + 1) * inv - 1.0;
  return area_element(x0, y0) - area_element(x0, y1) - area_element(x1, y0) +
         area_element(x1, y1);
}

Eigen::Vector3f Cubemap::sample(const Eigen::Vector3d& direction) const {
  const CubeTexel t = cube_texel_from_direction(direction);
  const int x = std::clamp(static_cast<int>(t.u * face_size), 0, face_size - 1);
  const int y = std::clamp(static_cast<int>(t.v * face_size), 0, face_size - 1);
  const ImageRGBF& f = faces[static_cast<int>(t.face)];
  return {f.at(x, y, 0), f.at(x, y, 1), f.at(x, y, 2)};
}

}  // namespace probeless
