// Hole cores (hole_core_reference.hpp): depth holes whose whole clipped (2r+1)^2 window is
// hole get NEAR_MM, the depth of a surface nearer than the sensor's minimum range. Rows, then
// columns, each a sliding count of holes over its window: O(1) per pixel whatever r (a loop
// over the window per pixel cost 3.0 ms of a 640x480 frame at r = 20 on two CPU cores).
// NEAR_MM is a -D option.

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

// One work-item per column: the cores of the row results, and the filled depth.
__kernel void hole_core_fill(__global const ushort* depth, __global const uchar* rows,
                             __global ushort* out, int w, int h, int r) {
  const int x = get_global_id(0);
  if (x >= w) return;
  int full = 0;  // rows of the window whose segment is all hole
  for (int k = 0; k < min(r, h); ++k) full += rows[k * w + x];
  for (int y = 0; y < h; ++y) {
    if (y + r < h) full += rows[(y + r) * w + x];
    if (y - r - 1 >= 0) full -= rows[(y - r - 1) * w + x];
    const int span = min(h - 1, y + r) - max(0, y - r) + 1;
    const int i = y * w + x;
    out[i] = full == span ? (ushort)NEAR_MM : depth[i];
  }
}
