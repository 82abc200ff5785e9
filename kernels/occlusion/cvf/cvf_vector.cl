// Vector helpers of CVF's row-streaming kernels (cvf_guided.cl, cvf.cl), prepended to their
// source by the host: one work-item walks a strip of rows across the whole width in float16
// vectors of 16 columns; rows of running column sums carry PAD zero columns on each side.

#define VW 16
#define PAD 48
typedef float16 vf;
typedef int16 vi;
// Unaligned vector access to global memory. PoCL's vload16/vstore16 assembled a float16 from
// eight 8-byte moves (perf); a dereference through a type with the element's alignment is one
// unaligned vector move.
typedef float16 __attribute__((aligned(4))) vf_unaligned;
typedef uchar16 __attribute__((aligned(1))) uc16_unaligned;
typedef ushort16 __attribute__((aligned(2))) us16_unaligned;
#define LOADF(p) (*(__global const vf_unaligned*)(p))
#define STOREF(p, v) (*(__global vf_unaligned*)(p) = (v))
#define LOADU8(p) (*(__global const uc16_unaligned*)(p))
#define STOREU8(p, v) (*(__global uc16_unaligned*)(p) = (v))
#define LOADU16(p) (*(__global const us16_unaligned*)(p))

inline vi lanes(void) {
  return (vi)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
}

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

// 16 interleaved RGB8 pixels (48 bytes) as three float vectors in [0, 255].
inline void load_rgb16(__global const uchar* p, vf* r, vf* g, vf* b) {
  const uchar16 a = LOADU8(p), m = LOADU8(p + 16), c = LOADU8(p + 32);
  const uchar16 ra =
      __builtin_shufflevector(a, m, 0, 3, 6, 9, 12, 15, 18, 21, 24, 27, 30, 0, 0, 0, 0, 0);
  const uchar16 ga =
      __builtin_shufflevector(a, m, 1, 4, 7, 10, 13, 16, 19, 22, 25, 28, 31, 0, 0, 0, 0, 0);
  const uchar16 ba =
      __builtin_shufflevector(a, m, 2, 5, 8, 11, 14, 17, 20, 23, 26, 29, 0, 0, 0, 0, 0, 0);
  *r = convert_float16(
      __builtin_shufflevector(ra, c, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 17, 20, 23, 26, 29));
  *g = convert_float16(
      __builtin_shufflevector(ga, c, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 18, 21, 24, 27, 30));
  *b = convert_float16(
      __builtin_shufflevector(ba, c, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 16, 19, 22, 25, 28, 31));
}
