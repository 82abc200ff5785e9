// Hole cores (hole_core_reference.hpp): depth holes whose whole clipped (2r+1)^2 window is
// hole get NEAR_MM, the depth of a surface nearer than the sensor's minimum range. Rows, then
// columns. NEAR_MM is a -D option. Measured at 640x480, r = 20, two CPU cores on PoCL
// (HoleCore.DISABLED_CostVga): a window loop per pixel in both passes ~3 ms; sliding counts,
// one work-item per row and per column, 0.76 ms (a column walk touches a cache line per row);
// with 16 columns a work-item in the column pass 0.47-0.63 ms. (A per-pixel early exit in the
// row pass measured 2.0 ms on that test's wide hole.)

// One work-item per row: rows[x] = 1 where [x - r, x + r] (clipped) is all hole.
__kernel void hole_core_rows(__global const ushort* depth, __global uchar* rows, int w, int h,
                             int r) {
  const int y = get_global_id(0);
  if (y >= h) return;
  __global const ushort* in = depth + y * w;
  __global uchar* out = rows + y * w;
  int holes = 0;  // holes in [x - r, x + r] clipped
  for (int k = 0; k < min(r, w); ++k) holes += in[k] == 0;
  for (int x = 0; x < w; ++x) {
    if (x + r < w) holes += in[x + r] == 0;
    if (x - r - 1 >= 0) holes -= in[x - r - 1] == 0;
    const int span = min(w - 1, x + r) - max(0, x - r) + 1;
    out[x] = holes == span;
  }
}

// 16 adjacent columns a work-item (x0 = 16 gid), sliding down the rows with vector counts:
// one 16-byte load per row instead of 16 cache lines; a partial last group goes a column at a
// time.
__kernel void hole_core_fill(__global const ushort* depth, __global const uchar* rows,
                             __global ushort* out, int w, int h, int r) {
  const int x0 = get_global_id(0) * 16;
  if (x0 >= w) return;
  if (x0 + 16 > w) {  // the last, partial group: one column at a time
    for (int x = x0; x < w; ++x) {
      int full = 0;
      for (int k = 0; k < min(r, h); ++k) full += rows[k * w + x];
      for (int y = 0; y < h; ++y) {
        if (y + r < h) full += rows[(y + r) * w + x];
        if (y - r - 1 >= 0) full -= rows[(y - r - 1) * w + x];
        const int span = min(h - 1, y + r) - max(0, y - r) + 1;
        out[y * w + x] = full == span ? (ushort)NEAR_MM : depth[y * w + x];
      }
    }
    return;
  }
  short16 full = (short16)(0);
  for (int k = 0; k < min(r, h); ++k) full += convert_short16(vload16(0, rows + k * w + x0));
  for (int y = 0; y < h; ++y) {
    if (y + r < h) full += convert_short16(vload16(0, rows + (y + r) * w + x0));
    if (y - r - 1 >= 0) full -= convert_short16(vload16(0, rows + (y - r - 1) * w + x0));
    const short span = (short)(min(h - 1, y + r) - max(0, y - r) + 1);
    const ushort16 d = vload16(0, depth + y * w + x0);
    vstore16(select(d, (ushort16)(NEAR_MM), full == (short16)(span)), 0, out + y * w + x0);
  }
}
