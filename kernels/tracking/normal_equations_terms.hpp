#pragma once
// What accumulate_reference (normal_equations.cpp) and accumulate_cpu
// (normal_equations_cpu.cpp) share: one residual's terms added into the sums, for a float or a
// 4-lane vector of floats, and the bilinear read of a level's intensity.
#include <cmath>

#include "kernels/tracking/frame_pyramid.hpp"
#include "kernels/tracking/normal_equations.hpp"

namespace probeless::tracking::detail {

// s[kH..] += w J^T J (upper triangle, row-major), s[kG..] += w J^T r.
template <class T>
inline void add_residual(T* s, const T* j, T r, T weight) {
  int k = kH;
  for (int a = 0; a < 6; ++a) {
    const T wa = weight * j[a];
    for (int b = a; b < 6; ++b) s[k++] += wa * j[b];
    s[kG + a] += wa * r;
  }
}

// (u, v) inside [0, w - 1) x [0, h - 1): the caller checks.
inline float bilinear(const ImageF& img, float u, float v) {
  const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
  const float fx = u - float(x0), fy = v - float(y0);
  const float* r0 = img.row(y0) + x0;
  const float* r1 = img.row(y0 + 1) + x0;
  return (1.0f - fy) * ((1.0f - fx) * r0[0] + fx * r0[1]) + fy * ((1.0f - fx) * r1[0] + fx * r1[1]);
}

}  // namespace probeless::tracking::detail
