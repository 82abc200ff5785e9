// Hole cores (hole_core_reference.hpp): depth holes whose whole clipped (2r+1)^2 window is
// hole get NEAR_MM, the depth of a surface nearer than the sensor's minimum range. Rows, then
// columns. NEAR_MM is a -D option.

__kernel void hole_core_rows(__global const ushort* depth, __global uchar* rows, int w, int h,
                             int r) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  __global const ushort* row = depth + y * w;
  uchar all = 1;
  for (int k = max(0, x - r); k <= min(w - 1, x + r); ++k) all &= row[k] == 0;
  rows[y * w + x] = all;
}

__kernel void hole_core_fill(__global const ushort* depth, __global const uchar* rows,
                             __global ushort* out, int w, int h, int r) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  uchar all = 1;
  for (int k = max(0, y - r); k <= min(h - 1, y + r); ++k) all &= rows[k * w + x];
  const int i = y * w + x;
  out[i] = all ? (ushort)NEAR_MM : depth[i];
}
