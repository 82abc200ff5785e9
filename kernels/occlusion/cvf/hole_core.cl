// Hole cores (hole_core_reference.hpp): depth holes whose whole clipped (2r+1)^2 window is
// hole get NEAR_MM, the depth of a surface nearer than the sensor's minimum range; and, for the
// stages after the matte, the holes around a core (a core within the window) too. Each is a
// pass along the rows, then one down the columns, counting pixels of one value in the window.
// NEAR_MM is a -D option. Measured at 640x480, r = 20, two CPU cores on PoCL
// (HoleCore.DISABLED_CostVga): a window loop per pixel in both passes ~3 ms; sliding counts,
// one work-item per row and per column, 0.76 ms (a column walk touches a cache line per row);
// with 16 columns a work-item in the column pass 0.47-0.63 ms. (A per-pixel early exit in the
// row pass measured 2.0 ms on that test's wide hole.) The rows as bit sets (hole_core_rows)
// then took both passes from 0.78-0.80 to 0.42-0.45 ms in one run at load 11; work-groups of
// one work-item (hole_core.cpp) from 0.59-0.68 to 0.33-0.52 ms, quiet.

// A hole of a far surface's colour (hole_core_reference.hpp far_hole_colour(); WHITE_MIN and
// BLACK_MAX are -D options) is no core candidate.
inline int far_hole_colour(__global const uchar* c) {
  return (c[0] >= WHITE_MIN && c[1] >= WHITE_MIN && c[2] >= WHITE_MIN) ||
         (c[0] <= BLACK_MAX && c[1] <= BLACK_MAX && c[2] <= BLACK_MAX);
}

// The rule of both passes: n of the window's span pixels hit, all of them (need_all) or any.
inline int window_rule(int n, int span, int need_all) {
  return need_all ? n == span : n > 0;
}

// Rows with their margins (w + 2 r) up to 64 * ROW_WORDS = 4096 pixels are bit sets, 64 pixels
// a word; wider ones take the sliding count (hole_core_row_sliding).
#define ROW_WORDS 64

// Bits of b[0..words) moved by s pixels towards higher x (up) or lower x (down), word i.
inline ulong bits_up(const ulong* b, int words, int i, int s) {
  const int j = i - (s >> 6), k = s & 63;
  const ulong lo = j >= 0 && j < words ? b[j] : 0UL;
  const ulong hi = j >= 1 && j - 1 < words ? b[j - 1] : 0UL;
  return k ? (lo << k) | (hi >> (64 - k)) : lo;
}
inline ulong bits_down(const ulong* b, int words, int i, int s) {
  const int j = i + (s >> 6), k = s & 63;
  const ulong lo = j >= 0 && j < words ? b[j] : 0UL;
  const ulong hi = j + 1 < words ? b[j + 1] : 0UL;
  return k ? (lo >> k) | (hi << (64 - k)) : lo;
}

// Pixel x counts as `value`: with use_colour (the cores' pass), not where its colour is a far
// surface's.
inline int counts_as(__global const ushort* in, __global const uchar* rgb, int use_colour, int x,
                     ushort value) {
  return in[x] == value && !(use_colour && far_hole_colour(rgb + 3 * x));
}

// The sliding count along one row: rows[x] = 1 where [x - r, x + r] (clipped) holds only
// `value` (need_all) or at least one `value` (else).
inline void hole_core_row_sliding(__global const ushort* in, __global const uchar* rgb,
                                  int use_colour, __global uchar* out, int w, int r, ushort value,
                                  int need_all) {
  int n = 0;  // pixels of `value` in [x - r, x + r] clipped
  for (int k = 0; k < min(r, w); ++k) n += counts_as(in, rgb, use_colour, k, value);
  for (int x = 0; x < w; ++x) {
    if (x + r < w) n += counts_as(in, rgb, use_colour, x + r, value);
    if (x - r - 1 >= 0) n -= counts_as(in, rgb, use_colour, x - r - 1, value);
    const int span = min(w - 1, x + r) - max(0, x - r) + 1;
    out[x] = window_rule(n, span, need_all);
  }
}

// One work-item per row, the same rule as a dilation of a bit set: the pixels that break it
// (each pixel that is not `value` for need_all, each `value` pixel else) dilated by r, in
// steps {-s, 0, s} that double the covered span (1, 3, 9, 7 for r = 20); bits past the row's
// end are 0, which clips the windows at the frame (measured: the file's head; in `bench
// pipeline`'s PoCL profile the sliding row pass had been the fifth-largest kernel).
// With use_colour (the cores' pass), a pixel of `value` whose colour is a far surface's counts
// as not `value`: the bits are then built a pixel at a time.
__kernel void hole_core_rows(__global const ushort* depth, __global uchar* rows, int w, int h,
                             int r, ushort value, int need_all, __global const uchar* colour,
                             int use_colour) {
  const int y = get_global_id(0);
  if (y >= h) return;
  __global const ushort* in = depth + y * w;
  __global const uchar* rgb = colour + 3 * y * w;
  __global uchar* out = rows + y * w;
  // The bit of pixel x is x + r: the steps' partial sums reach r either way, so a pixel's
  // bit must be able to leave the row by r and come back.
  const int row_words = (w + 63) >> 6, words = (w + 2 * r + 63) >> 6;
  if (words > ROW_WORDS) {
    hole_core_row_sliding(in, rgb, use_colour, out, w, r, value, need_all);
    return;
  }
  ulong a[ROW_WORDS], b[ROW_WORDS];
  const ushort16 lane_bit =
      (ushort16)(1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768);
  for (int i = 0; i < row_words; ++i) {
    ulong word = 0;
    for (int c = 0; c < 4; ++c) {
      const int x0 = 64 * i + 16 * c;
      uint chunk = 0;
      if (x0 + 16 <= w && !use_colour) {
        const short16 hit = as_short16(vload16(0, in + x0) == (ushort16)(value));
        const ushort16 m = as_ushort16(need_all ? ~hit : hit) & lane_bit;
        const ushort8 m8 = m.lo + m.hi;
        const ushort4 m4 = m8.lo + m8.hi;
        const ushort2 m2 = m4.lo + m4.hi;
        chunk = (uint)(m2.x + m2.y);
      } else {
        for (int k = 0; k < 16 && x0 + k < w; ++k)
          chunk |= (uint)(counts_as(in, rgb, use_colour, x0 + k, value) != need_all) << k;
      }
      word |= (ulong)chunk << (16 * c);
    }
    b[i] = word;
  }
  for (int i = 0; i < words; ++i) a[i] = bits_up(b, row_words, i, r);
  for (int covered = 0; covered < r;) {
    const int s = min(2 * covered + 1, r - covered);
    for (int i = 0; i < words; ++i)
      b[i] = a[i] | bits_up(a, words, i, s) | bits_down(a, words, i, s);
    for (int i = 0; i < words; ++i) a[i] = b[i];
    covered += s;
  }
  // need_all: the rule holds where no breaking pixel is within r; else where one is.
  for (int x = 0; x < w; ++x) {
    const int dilated = (int)((a[(x + r) >> 6] >> ((x + r) & 63)) & 1UL);
    out[x] = need_all ? !dilated : dilated;
  }
}

// The column pass over `rows`, the same rule; where it holds and the depth is unknown (or
// already NEAR_MM), NEAR_MM, else the depth. 16 adjacent columns a work-item (x0 = x_begin +
// 16 gid), one 16-byte load per row instead of 16 cache lines; a partial last group a column
// at a time. Only columns [x_begin, x_end) and rows [y_begin, y_end) are written (the pixels
// the stages after need, HoleCoreFill::run()); `rows` must hold rows y_begin - r - 1 ..
// y_end + r.
__kernel void hole_core_fill(__global const ushort* depth, __global const uchar* rows,
                             __global ushort* out, int w, int h, int r, int need_all, int x_begin,
                             int x_end, int y_begin, int y_end) {
  const int x0 = x_begin + get_global_id(0) * 16;
  if (x0 >= x_end) return;
  // n: the count over rows [y_begin - r - 1, y_begin + r - 1] (clipped), what the step of
  // row y_begin expects (it adds row y_begin + r and takes row y_begin - r - 1 away).
  const int first = max(0, y_begin - r - 1), last = min(h, y_begin + r);
  if (x0 + 16 > x_end) {
    for (int x = x0; x < x_end; ++x) {
      int n = 0;
      for (int k = first; k < last; ++k) n += rows[k * w + x];
      for (int y = y_begin; y < y_end; ++y) {
        if (y + r < h) n += rows[(y + r) * w + x];
        if (y - r - 1 >= 0) n -= rows[(y - r - 1) * w + x];
        const int span = min(h - 1, y + r) - max(0, y - r) + 1;
        const ushort d = depth[y * w + x];
        const int near = window_rule(n, span, need_all) && (d == 0 || d == NEAR_MM);
        out[y * w + x] = near ? (ushort)NEAR_MM : d;
      }
    }
    return;
  }
  short16 n = (short16)(0);
  for (int k = first; k < last; ++k) n += convert_short16(vload16(0, rows + k * w + x0));
  for (int y = y_begin; y < y_end; ++y) {
    if (y + r < h) n += convert_short16(vload16(0, rows + (y + r) * w + x0));
    if (y - r - 1 >= 0) n -= convert_short16(vload16(0, rows + (y - r - 1) * w + x0));
    const short span = (short)(min(h - 1, y + r) - max(0, y - r) + 1);
    const short16 rule = need_all ? n == (short16)(span) : n > (short16)(0);
    const ushort16 d = vload16(0, depth + y * w + x0);
    const short16 unknown = as_short16(d == (ushort16)(0)) | as_short16(d == (ushort16)(NEAR_MM));
    vstore16(select(d, (ushort16)(NEAR_MM), as_ushort16(rule & unknown)), 0, out + y * w + x0);
  }
}
