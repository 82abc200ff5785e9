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

}  // namespace probeless::envmap
