// The "Crabb et al." baseline (crabb_matte_reference.cpp): threshold the real depth at the
// virtual object's mean depth. crabb_mean runs as one work-group and writes (sum, count).
__kernel void crabb_mean(__global const float* virtual_mm, int n, __global float* stats) {
  __local float sums[256];
  __local float counts[256];
  const int l = get_local_id(0);
  float s = 0.0f, c = 0.0f;
  for (int i = l; i < n; i += 256) {
    const float v = virtual_mm[i];
    if (v > 0.0f) {
      s += v;
      c += 1.0f;
    }
  }
  sums[l] = s;
  counts[l] = c;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int step = 128; step > 0; step >>= 1) {
    if (l < step) {
      sums[l] += sums[l + step];
      counts[l] += counts[l + step];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (l == 0) {
    stats[0] = sums[0];
    stats[1] = counts[0];
  }
}

__kernel void crabb_matte(__global const ushort* real_mm, __global const float* virtual_mm,
                          __global const float* stats, int w, int h, __global float* alpha) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const float threshold = stats[1] > 0.0f ? stats[0] / stats[1] : 0.0f;
  const ushort d = real_mm[i];
  alpha[i] = !(virtual_mm[i] > 0.0f) ? 0.0f : (d != 0 && (float)d < threshold) ? 0.0f : 1.0f;
}
