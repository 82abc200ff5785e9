#pragma once
// Push-pull inpainting of a keyframe's unobserved texels (push_pull.cl; docs/light-capture.md).
// Per face: pull (weighted 2 x 2 means down to 1 x 1), push (holes take their parent's value,
// coarse to fine). Faces without a single observed texel are then seeded along their edges
// from the adjacent faces' filled borders and pushed-pulled again, in passes until every face
// that can be reached has data (at most three: a face opposite the only observed one needs
// its four neighbours first). Observed texels never change. Everything is decided on the
// device (two launches, no read-back): one work-group per face runs a whole pyramid, then one
// work-group runs the passes across face edges.
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
  // Fills texels (n x 6n) in place. Enqueues only.
  void fill(DeviceImage<float, 4>& texels);
  // After fill: the faces that had observed texels (a mask; blocking read).
  int observed_faces();

 private:
  ComputeContext& ctx_;
  ::cl::Kernel pull_push_, fill_empty_;
  ::cl::Buffer pyramid_;     // levels 1..top of all six faces
  ::cl::Buffer face_state_;  // int[6]: 0 no data, 2 observed, 1 filled from neighbours
  int face_size_ = 0;
  std::size_t local_ = 1, local_fill_ = 1;
};

}  // namespace probeless::envmap
