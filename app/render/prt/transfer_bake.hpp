#pragma once
// The bake's inner loop (docs/prt.md "Estimator"): for each receiver vertex, cosine-weighted
// directions in its tangent frame, one visibility ray each against the occluders, and the SH
// basis of every direction that escapes summed into its 25 coefficients. Used by bake_prt;
// separate so the estimator can be read (and tested) without the cache and the grid.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "app/render/mesh.hpp"
#include "app/render/prt/bvh.hpp"
#include "app/render/prt/prt.hpp"

namespace probeless::prt {

// What a visibility ray can meet: the object (optionally a mirror) and the solid half-space
// under a plane. Rays start `epsilon` off the surface along the normal so that they do not hit
// the triangle they start on.
struct Occluders {
  const TriangleBvh* object = nullptr;        // null: no object (the ground-alone bake)
  const render::Mesh* object_mesh = nullptr;  // its indices and normals, for reflections
  bool mirror = false;
  float reflectance = 1.f;
  // Per triangle, in place of the two above (Scene::triangle_reflectance); 0 blocks.
  const std::vector<float>* triangle_reflectance = nullptr;
  int max_bounces = 4;
  // Unit normal and offset of the plane n . x + d = 0; above is n . x + d > 0.
  std::optional<Eigen::Vector4f> plane;
  float epsilon = 1e-5f;

  struct Result {
    float weight = 0;        // 0: blocked; 1: escaped; reflectance^k after k mirror bounces
    bool reflected = false;  // direction is then where it left the last mirror
    Eigen::Vector3f direction;
  };
  Result trace(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction) const;
};

// T_i(x) = 1/N sum_s weight_s y_i(w_s) over the N directions (cosine-weighted: the density
// cos/pi cancels the clamped cosine and the 1/pi, Sloan et al. 2002 sec. 5 with importance
// sampling). `directions` are around +z and turned into each vertex's frame. Vertices are
// shared out to `threads` threads in chunks; each is computed alone, so the result does not
// depend on the thread count.
Transfer bake_transfer(const std::vector<Eigen::Vector3f>& positions,
                       const std::vector<Eigen::Vector3f>& normals, const Occluders& occluders,
                       const std::vector<Eigen::Vector3d>& directions, unsigned threads);

}  // namespace probeless::prt
