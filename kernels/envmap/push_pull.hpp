#pragma once
// Push-pull inpainting of a keyframe's unobserved texels (push_pull.cl; docs/light-capture.md).
// Per face: pull (weighted 2 x 2 means down to 1 x 1), push (holes take their parent's value,
// coarse to fine). Faces without a single observed texel are then seeded along their edges
// from the adjacent faces' filled borders and pushed-pulled again, in passes until every face
// that can be reached has data (at most three: a face opposite the only observed one needs
// its four neighbours first). Observed texels never change.
#include <vector>

#include "kernels/envmap/envmap_types.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::envmap {

// Bits 0..5: faces in OpenGL order. The faces that share an edge with face f: all but f and
// its opposite, f ^ 1.
inline int adjacent_faces(int face) {
  return 0x3F & ~(3 << (face & ~1));
}

class PushPull {
 public:
  explicit PushPull(ComputeContext& ctx);
  // Fills texels (n x 6n) in place. Enqueues the passes; reads back six weights (blocking)
  // to learn which faces had no data. Returns the faces that had observed texels (a mask).
  int fill(DeviceImage<float, 4>& texels);

 private:
  void pull_push(DeviceImage<float, 4>& texels, int face_mask);
  void resize_levels(int n);

  ComputeContext& ctx_;
  ::cl::Kernel pull_, push_, seed_;
  std::vector<DeviceImage<float, 4>> levels_;  // 1..top: sizes ceil(n / 2^k) down to 1
  int face_size_ = 0;
};

}  // namespace probeless::envmap
