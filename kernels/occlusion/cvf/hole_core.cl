// Hole cores (hole_core_reference.hpp): depth holes whose whole clipped (2r+1)^2 window is
// hole get NEAR_MM, the depth of a surface nearer than the sensor's minimum range; and, for the
// stages after the matte, the holes around a core (a core within the window) too. Each is a
// pass along the rows, then one down the columns, counting pixels of one value in the window.
// NEAR_MM is a -D option. Measured at 640x480, r = 20, two CPU cores on PoCL
// (HoleCore.DISABLED_CostVga): a window loop per pixel in both passes ~3 ms; sliding counts,
// one work-item per row and per column, 0.76 ms (a column walk touches a cache line per row);
// with 16 columns a work-item in the column pass 0.47-0.63 ms. (A per-pixel early exit in the
// row pass measured 2.0 ms on that test's wide hole.)

// The rule of both passes: n of the window's span pixels hit, all of them (need_all) or any.
inline int window_rule(int n, int span, int need_all) {
  return need_all ? n == span : n > 0;
}

// One work-item per row: rows[x] = 1 where [x - r, x + r] (clipped) holds only `value`
// (need_all) or at least one `value` (else).
__kernel void hole_core_rows(__global const ushort* depth, __global uchar* rows, int w, int h,
                             int r, ushort value, int need_all) {
  const int y = get_global_id(0);
  if (y >= h) return;
  __global const ushort* in = depth + y * w;
  __global uchar* out = rows + y * w;
  int n = 0;  // pixels of `value` in [x - r, x + r] clipped
  for (int k = 0; k < min(r, w); ++k) n += in[k] == value;
  for (int x = 0; x < w; ++x) {
    if (x + r < w) n += in[x + r] == value;
    if (x - r - 1 >= 0) n -= in[x - r - 1] == value;
    const int span = min(w - 1, x + r) - max(0, x - r) + 1;
    out[x] = window_rule(n, span, need_all);
  }
}

// The column pass over `rows`, the same rule; where it holds and the depth is unknown (or
// already NEAR_MM), NEAR_MM, else the depth. 16 adjacent columns a work-item (x0 = 16 gid),
// one 16-byte load per row instead of 16 cache lines; a partial last group a column at a time.
__kernel void hole_core_fill(__global const ushort* depth, __global const uchar* rows,
                             __global ushort* out, int w, int h, int r, int need_all) {
  const int x0 = get_global_id(0) * 16;
  if (x0 >= w) return;
  if (x0 + 16 > w) {
    for (int x = x0; x < w; ++x) {
      int n = 0;
      for (int k = 0; k < min(r, h); ++k) n += rows[k * w + x];
      for (int y = 0; y < h; ++y) {
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
  for (int k = 0; k < min(r, h); ++k) n += convert_short16(vload16(0, rows + k * w + x0));
  for (int y = 0; y < h; ++y) {
    if (y + r < h) n += convert_short16(vload16(0, rows + (y + r) * w + x0));
    if (y - r - 1 >= 0) n -= convert_short16(vload16(0, rows + (y - r - 1) * w + x0));
    const short span = (short)(min(h - 1, y + r) - max(0, y - r) + 1);
    const short16 rule = need_all ? n == (short16)(span) : n > (short16)(0);
    const ushort16 d = vload16(0, depth + y * w + x0);
    const short16 unknown = as_short16(d == (ushort16)(0)) | as_short16(d == (ushort16)(NEAR_MM));
    vstore16(select(d, (ushort16)(NEAR_MM), as_ushort16(rule & unknown)), 0, out + y * w + x0);
  }
}
