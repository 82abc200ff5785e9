// Vector helpers of CVF's row-streaming kernels (cvf_guided.cl, cvf.cl), prepended to their
// source by the host after common/vector16.cl: rows of running column sums carry PAD zero
// columns on each side.

#define PAD 48

// Inclusive prefix sum across the 16 lanes.
inline vf prefix16(vf d) {
  const vf z = (vf)(0.0f);
  d += __builtin_shufflevector(z, d, 0, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30);
  d += __builtin_shufflevector(z, d, 0, 1, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29);
  d += __builtin_shufflevector(z, d, 0, 1, 2, 3, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27);
  d += __builtin_shufflevector(z, d, 0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23);
  return d;
}

// Window sums over 2 r + 1 columns of the 16 columns from x on, from the running carry (the
// window sum of column x - 1 in every lane): S(x) = S(x - 1) + col(x + r) - col(x - r - 1), so
// the cost per column does not depend on r (r <= 16, the zero padding). `col` points at
// column 0. The carry stays a vector (a broadcast of lane 15): kept in a scalar, it went
// through the stack and made a store-to-load chain of every row (perf, docs/occlusion.md).
inline vf running_window_sums(__global const float* col, int x, int r, vf* carry) {
  const vf d = LOADF(col + x + r) - LOADF(col + x - r - 1);
  const vf s = prefix16(d) + *carry;
  *carry =
      __builtin_shufflevector(s, s, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15);
  return s;
}

// Stores the lanes of v that lie inside the row (x < w).
inline void store_row(__global float* dst, int x0, int w, vf v) {
  if (x0 + VW <= w) {
    STOREF(dst + x0, v);
  } else {
    float t[VW];
    vstore16(v, 0, t);
    for (int k = 0; x0 + k < w; ++k) dst[x0 + k] = t[k];
  }
}

inline vf load_row(__global const float* src, int x0, int w) {
  if (x0 + VW <= w) return LOADF(src + x0);
  float t[VW];
  for (int k = 0; k < VW; ++k) t[k] = x0 + k < w ? src[x0 + k] : 0.0f;
  return vload16(0, t);
}
