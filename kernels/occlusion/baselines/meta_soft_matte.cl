// Meta-Quest-style soft occlusion (meta_soft_matte_reference.cpp): min, max and mean of the
// valid depth around the pixel; blend of the visibilities of min and max by smoothstep where
// they differ, else the visibility of the mean.
__kernel void meta_soft_matte(__global const ushort* real_mm, __global const float* virtual_mm,
                              int w, int h, int radius, float relative_range, float blend_threshold,
                              float fg_level, float bg_level, __global float* alpha) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const float v = virtual_mm[i];
  if (!(v > 0.0f)) {
    alpha[i] = 0.0f;
    return;
  }
  float lo = 0.0f, hi = 0.0f, sum = 0.0f;
  int n = 0;
  for (int j = max(0, y - radius); j <= min(h - 1, y + radius); ++j)
    for (int k = max(0, x - radius); k <= min(w - 1, x + radius); ++k) {
      const ushort d16 = real_mm[j * w + k];
      if (d16 == 0) continue;
      const float d = (float)d16;
      lo = n ? fmin(lo, d) : d;
      hi = n ? fmax(hi, d) : d;
      sum += d;
      ++n;
    }
  if (n == 0) {
    alpha[i] = 1.0f;
    return;
  }
  const float range = relative_range * v;
  const float mean = sum / (float)n;
  float a = clamp((mean - v) / range, 0.0f, 1.0f);
  const float vlo = clamp((lo - v) / range, 0.0f, 1.0f), vhi = clamp((hi - v) / range, 0.0f, 1.0f);
  if (vhi - vlo > blend_threshold) {
    const float t = (mean - lo) / (hi - lo);
    const float s = clamp((t - fg_level) / (bg_level - fg_level), 0.0f, 1.0f);
    a = vlo + (vhi - vlo) * (s * s * (3.0f - 2.0f * s));
  }
  alpha[i] = a;
}
