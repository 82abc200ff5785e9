#pragma once
// SH projection of a small cubemap (m x 6m texels, envmap_types.hpp layout) with the basis
// times the exact texel solid angle tabulated once: per frame it is one pass of
// multiply-adds, a fraction of a millisecond for 32 px faces, where core's project_sh
// re-evaluates 25 polynomials per texel. Same result as project_sh (tests/unit/light).
#include <vector>

#include "core/sh.hpp"
#include "kernels/envmap/envmap_types.hpp"

namespace probeless::light {

class ShProjector {
 public:
  explicit ShProjector(int face_size, int bands = kShMaxBands);
  // The SH of a keyframe seen from another position through the room box (reprojection
  // constants from envmap::reprojection_constants), from the keyframe's own m-px faces: each
  // target texel's basis x solid angle is spread over the keyframe texels its samples x
  // samples sub-directions land on (bilinear weights, as envmap::reproject_keyframe samples),
  // so that project() of the keyframe's box-filtered faces is the SH of its reprojection,
  // without reprojecting every frame. Built once per keyframe (~5 ms at 32 px).
  ShProjector(int face_size, const envmap::ParallaxConstants& reprojection, int samples = 4,
              int bands = kShMaxBands);
  int face_size() const { return face_size_; }
  ShRgb project(const envmap::ImageRGBAF& faces) const;

 private:
  int face_size_;
  int bands_;
  std::vector<float> table_;  // [texel][coefficient], texel in image order
};

}  // namespace probeless::light
