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
// With need_all (the cores' pass), core_rows[y] = 1 for every row y that got a core (the rim's
// passes skip the rows far from any; the host zeroes the flags, every writer writes 1).
__kernel void hole_core_fill(__global const ushort* depth, __global const uchar* rows,
                             __global ushort* out, int w, int h, int r, int need_all, int x_begin,
                             int x_end, int y_begin, int y_end, __global uchar* core_rows) {
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
        if (near && need_all) core_rows[y] = 1;
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
    if (need_all && any(rule & unknown)) core_rows[y] = 1;
  }
}

// The near occluder's rim that follows it (hole_core_reference.hpp
// mark_near_occluders_reference() with colour): a hole with a core within r is marked where its
// colour is nearer the mean colour of those core pixels than the mean colour of the measured
// pixels within m (none there: within CORE_COLOUR_SQ of the core's mean, a -D option). Two
// passes as above: along the rows the window sums of the core pixels (r) and of the measured
// ones (m), then down 16 columns a work-item, where the decision is made. Rows far from any
// core are skipped (the cores' pass flags its rows): a frame without a near occluder costs
// next to nothing. A first version over the whole objects' rectangle that also copied the
// image cost 3.9 CPU-ms a frame in `bench occlusion`, which has no cores (docs/occlusion.md
// "The rim that follows the occluder").

// One pixel's contribution: core pixel count and colour, measured pixel count and colour.
inline void rim_terms(__global const ushort* depth, __global const ushort* filled,
                      __global const uchar* colour, int i, int4* core, int4* meas) {
  const int4 c = (int4)(1, colour[3 * i], colour[3 * i + 1], colour[3 * i + 2]);
  *core = filled[i] == NEAR_MM ? c : (int4)(0);
  *meas = depth[i] != 0 ? c : (int4)(0);
}

// One work-item per row, columns [x_begin, x_end): sums[8 i .. 8 i + 8) = the core pixels'
// count and colour sums over [x - r, x + r], then the measured pixels' over [x - m, x + m]
// (clipped); `filled` is read r px either side. Counts <= 2 r + 1 and colour sums
// <= 255 (2 r + 1) fit 16 bits for r <= 128.
__kernel void near_rim_rows(__global const ushort* depth, __global const ushort* filled,
                            __global const uchar* colour, __global ushort* sums, int w, int h,
                            int r, int m, int x_begin, int x_end,
                            __global const uchar* core_rows, __global uchar* rim_rows) {
  const int y = get_global_id(0);
  const int row = y * w;
  // rim_rows[y]: a core within r rows, where near_rim_mark looks for a rim. It reads a row's
  // sums only for such rows, through windows of max(r, m) rows: nothing more to do where no
  // core is that near.
  const int reach = r + max(r, m);
  int any_core = 0, near_core = 0;
  for (int j = max(0, y - reach); j <= min(h - 1, y + reach); ++j) {
    any_core |= core_rows[j];
    near_core |= core_rows[j] && abs(j - y) <= r;
  }
  rim_rows[y] = (uchar)near_core;
  if (!any_core) return;
  int4 core = (int4)(0), meas = (int4)(0), a, b;
  // The windows of x_begin but for their last column, which the first step adds.
  for (int k = max(0, x_begin - r); k <= min(w - 1, x_begin + r - 1); ++k) {
    rim_terms(depth, filled, colour, row + k, &a, &b);
    core += a;
  }
  for (int k = max(0, x_begin - m); k <= min(w - 1, x_begin + m - 1); ++k) {
    rim_terms(depth, filled, colour, row + k, &a, &b);
    meas += b;
  }
  for (int x = x_begin; x < x_end; ++x) {
    if (x + r < w) {
      rim_terms(depth, filled, colour, row + x + r, &a, &b);
      core += a;
    }
    if (x > x_begin && x - r - 1 >= 0) {
      rim_terms(depth, filled, colour, row + x - r - 1, &a, &b);
      core -= a;
    }
    if (x + m < w) {
      rim_terms(depth, filled, colour, row + x + m, &a, &b);
      meas += b;
    }
    if (x > x_begin && x - m - 1 >= 0) {
      rim_terms(depth, filled, colour, row + x - m - 1, &a, &b);
      meas -= b;
    }
    vstore8(convert_ushort8((int8)(core, meas)), row + x, sums);
  }
}

// The column pass over near_rim_rows' sums and the decision (rim_takes_core_colour() of
// hole_core_reference.hpp, the same integer and float operations): out = NEAR_MM on the rim
// that takes the core's colour, else the filled depth. In place (out may be filled: a pixel is
// read and written by one work-item; the sums were taken before): rows without a core within r
// are then not touched at all. 16 adjacent columns a work-item
// (x0 = x_begin + 16 gid; the last group takes what is left). `sums` must hold rows
// y_begin - max(r, m) .. y_end + max(r, m) - 1 of the columns, `filled` the pixels written.
__kernel void near_rim_mark(__global const ushort* depth, __global const ushort* filled,
                            __global const uchar* colour, __global const ushort* sums,
                            __global ushort* out, int w, int h, int r, int m, int x_begin,
                            int x_end, int y_begin, int y_end, __global const uchar* rim_rows) {
  const int x0 = x_begin + get_global_id(0) * 16;
  if (x0 >= x_end) return;
  const int n = min(16, x_end - x0);
  int4 core[16], meas[16];
  int valid = 0;  // the sums hold the windows of row y - 1
  for (int y = y_begin; y < y_end; ++y) {
    // No core within r rows: no rim here, the filled depth as it is (in place: `out` is
    // `filled`; the windows are counted afresh at the next row that has one).
    if (!rim_rows[y]) {
      valid = 0;
      continue;
    }
    if (!valid) {
      // The windows of row y but for their last row, which the step below adds.
      for (int k = 0; k < n; ++k) core[k] = meas[k] = (int4)(0);
      for (int j = max(0, y - r); j <= min(h - 1, y + r - 1); ++j)
        for (int k = 0; k < n; ++k)
          core[k] += convert_int4(vload4(0, sums + 8 * (j * w + x0 + k)));
      for (int j = max(0, y - m); j <= min(h - 1, y + m - 1); ++j)
        for (int k = 0; k < n; ++k)
          meas[k] += convert_int4(vload4(0, sums + 8 * (j * w + x0 + k) + 4));
    }
    for (int k = 0; k < n; ++k) {
      const int x = x0 + k;
      if (y + r < h) core[k] += convert_int4(vload4(0, sums + 8 * ((y + r) * w + x)));
      if (valid && y - r - 1 >= 0)
        core[k] -= convert_int4(vload4(0, sums + 8 * ((y - r - 1) * w + x)));
      if (y + m < h) meas[k] += convert_int4(vload4(0, sums + 8 * ((y + m) * w + x) + 4));
      if (valid && y - m - 1 >= 0)
        meas[k] -= convert_int4(vload4(0, sums + 8 * ((y - m - 1) * w + x) + 4));
      const int i = y * w + x;
      const ushort f = filled[i];
      ushort v = f;
      if (depth[i] == 0 && f != NEAR_MM && core[k].x > 0) {
        const int c[3] = {colour[3 * i], colour[3 * i + 1], colour[3 * i + 2]};
        const int cs[3] = {core[k].y, core[k].z, core[k].w};
        const int ms[3] = {meas[k].y, meas[k].z, meas[k].w};
        long dc = 0, dm = 0;
        for (int q = 0; q < 3; ++q) {
          const long a = (long)core[k].x * c[q] - cs[q];
          const long b = (long)meas[k].x * c[q] - ms[q];
          dc += a * a;
          dm += b * b;
        }
        int near;
        if (meas[k].x == 0) {
          near = dc < (long)CORE_COLOUR_SQ * core[k].x * core[k].x;
        } else {
          const float lhs = (float)dc * (float)(meas[k].x * meas[k].x);
          const float rhs = (float)dm * (float)(core[k].x * core[k].x);
          near = lhs < rhs;
        }
        if (near) v = (ushort)NEAR_MM;
      }
      out[i] = v;
    }
    valid = 1;
  }
}
