// ARCore-style soft occlusion (soft_ramp_matte_reference.cpp): 5x5 mean of the valid depth,
// then a linear ramp over +-half_width of the virtual depth.
__kernel void soft_ramp_matte(__global const ushort* real_mm, __global const float* virtual_mm,
                              int w, int h, int radius, float half_width, __global float* alpha) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const float v = virtual_mm[i];
  if (!(v > 0.0f)) {
    alpha[i] = 0.0f;
    return;
  }
  float sum = 0.0f;
  int n = 0;
  for (int j = max(0, y - radius); j <= min(h - 1, y + radius); ++j)
    for (int k = max(0, x - radius); k <= min(w - 1, x + radius); ++k) {
      const ushort d = real_mm[j * w + k];
      if (d != 0) {
        sum += (float)d;
        ++n;
      }
    }
  alpha[i] =
      n == 0 ? 1.0f : clamp((sum / (float)n - v) / (2.0f * half_width * v) + 0.5f, 0.0f, 1.0f);
}
