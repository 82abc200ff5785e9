#pragma once
// A cubemap of linear radiance. Face order and orientation follow OpenGL
// (GL_TEXTURE_CUBE_MAP_POSITIVE_X + i: +X, -X, +Y, -Y, +Z, -Z) so faces upload to GLES as
// they are; directions are in the world frame (z up).
#include <Eigen/Core>
#include <array>

#include "core/image.hpp"

namespace probeless {

enum class CubeFace : int { PosX = 0, NegX, PosY, NegY, PosZ, NegZ };

struct CubeTexel {
  CubeFace face;
  double u, v;  // in [0,1), texel centres at (i + 0.5) / size
};

// Direction (need not be unit) -> face and face coordinates, OpenGL convention.
CubeTexel cube_texel_from_direction(const Eigen::Vector3d& direction);
// Face coordinates -> unit direction.
Eigen::Vector3d cube_direction(CubeFace face, double u, double v);
// Exact solid angle of texel (x, y) on a face of size n (sums to 4 pi over the cube).
double cube_texel_solid_angle(int x, int y, int n);

struct Cubemap {
  int face_size = 0;
  std::array<ImageRGBF, 6> faces;

  Cubemap() = default;
  explicit Cubemap(int size) : face_size(size) {
    for (auto& f : faces) f = ImageRGBF(size, size);
  }
  ImageRGBF& face(CubeFace f) { return faces[static_cast<int>(f)]; }
  const ImageRGBF& face(CubeFace f) const { return faces[static_cast<int>(f)]; }
  // Nearest-texel lookup.
  Eigen::Vector3f sample(const Eigen::Vector3d& direction) const;
  bool operator==(const Cubemap&) const = default;
};

}  // namespace probeless
