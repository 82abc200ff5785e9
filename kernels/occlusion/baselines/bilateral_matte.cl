// The "Bilateral" baseline (bilateral_matte_reference.cpp): process pixels take the joint
// bilateral average of the infront (0) and behind (1) pixels of their window.
// ks = -1 / (2 sigma_s^2), kc = -1 / (2 sigma_c^2 255^2).
__kernel void bilateral_matte(__global const uchar* rgb, __global const uchar* categories, int w,
                              int h, int radius, float ks, float kc, __global float* alpha) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const uchar c = categories[i];  // 0 ignore, 1 behind, 2 infront, 3 process
  if (c != 3) {
    alpha[i] = c == 1 ? 1.0f : 0.0f;
    return;
  }
  const float r0 = rgb[3 * i], g0 = rgb[3 * i + 1], b0 = rgb[3 * i + 2];
  float sum = 0.0f, wsum = 0.0f;
  for (int j = max(0, y - radius); j <= min(h - 1, y + radius); ++j)
    for (int k = max(0, x - radius); k <= min(w - 1, x + radius); ++k) {
      const int q = j * w + k;
      const uchar cq = categories[q];
      if (cq != 1 && cq != 2) continue;
      const float dr = rgb[3 * q] - r0, dg = rgb[3 * q + 1] - g0, db = rgb[3 * q + 2] - b0;
      const float wq = exp(ks * (float)((k - x) * (k - x) + (j - y) * (j - y)) +
                           kc * (dr * dr + dg * dg + db * db));
      sum += cq == 1 ? wq : 0.0f;
      wsum += wq;
    }
  alpha[i] = wsum > 0.0f ? sum / wsum : 0.5f;
}
