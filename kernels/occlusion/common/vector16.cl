// Vector helpers shared by the occlusion stages' row-streaming kernels (CVF's cvf.cl and
// cvf_guided.cl, the temporal stabiliser), prepended to their source by the host: one
// work-item walks a strip of rows in float16 vectors of 16 columns.

#define VW 16
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
#define STOREU16(p, v) (*(__global us16_unaligned*)(p) = (v))

inline vi lanes(void) {
  return (vi)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
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
