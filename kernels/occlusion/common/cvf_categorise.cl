// The depth test of CVF and the baselines that share it (thesis 3.3.1): raw categories as
// bits, separable dilation, erosion of the infront/behind borders. The device side of
// categorise_reference.cpp.

#define CAT_IGNORE 0
#define CAT_BEHIND 1
#define CAT_INFRONT 2
#define CAT_PROCESS 3

// depth_tolerance_mm() of cvf_params.hpp: TOL_QUAD and TOL_Z0 are -D options; separate
// statements so that no fused multiply-add changes the last bit.
inline float tolerance_at(float tolerance_mm, float v) {
  const float d = v - TOL_Z0;
  float q = d * d;
  q = TOL_QUAD * q;
  return tolerance_mm + q;
}

// Raw depth test as bits: 0 off the object, else 1 << (category - 1).
__kernel void cvf_raw_bits(__global const ushort* real_mm, __global const float* virtual_mm,
                           __global uchar* bits, int w, int h, float tolerance_mm) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const float v = virtual_mm[i];
  const ushort r = real_mm[i];
  int c;
  if (!(v > 0.0f))
    c = CAT_IGNORE;
  else if (r == 0 || fabs((float)r - v) <= tolerance_at(tolerance_mm, v))
    c = CAT_PROCESS;
  else
    c = (float)r < v ? CAT_INFRONT : CAT_BEHIND;
  bits[i] = c == CAT_IGNORE ? 0 : (uchar)(1 << (c - 1));
}

// OR over the clipped window of radius r, along rows then along columns.
__kernel void cvf_dilate_rows(__global const uchar* src, __global uchar* dst, int w, int h, int r) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  __global const uchar* row = src + y * w;
  uchar v = 0;
  for (int k = max(0, x - r); k <= min(w - 1, x + r); ++k) v |= row[k];
  dst[y * w + x] = v;
}

__kernel void cvf_dilate_cols(__global const uchar* src, __global uchar* dst, int w, int h, int r) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  uchar v = 0;
  for (int k = max(0, y - r); k <= min(h - 1, y + r); ++k) v |= src[k * w + x];
  dst[y * w + x] = v;
}

// Erosion of the infront/behind border: infront pixels with a behind pixel nearby, and behind
// pixels with an infront one, become process (process pixels do not erode).
// Writes the categories and the process mask (for the band).
__kernel void cvf_erode(__global const uchar* raw_bits, __global const uchar* near_bits,
                        __global uchar* categories, __global uchar* process, int w, int h) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const uchar own = raw_bits[i];
  int c = own == 0 ? CAT_IGNORE : own == 1 ? CAT_BEHIND : own == 2 ? CAT_INFRONT : CAT_PROCESS;
  if ((c == CAT_INFRONT || c == CAT_BEHIND) && (near_bits[i] & ~own & 3) != 0) c = CAT_PROCESS;
  categories[i] = (uchar)c;
  process[i] = c == CAT_PROCESS ? 1 : 0;
}
