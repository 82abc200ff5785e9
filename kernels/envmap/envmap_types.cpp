#include "kernels/envmap/envmap_types.hpp"

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

}  // namespace probeless::envmap
