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
  int face_size() const { return face_size_; }
  ShRgb project(const envmap::ImageRGBAF& faces) const;

 private:
  int face_size_;
  int bands_;
  std::vector<float> table_;  // [texel][coefficient], texel in image order
};

}  // namespace probeless::light
