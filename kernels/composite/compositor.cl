// Compositing (thesis eq. 3.1): out = a * virtual + (1 - a) * real per channel, a = the
// occlusion matte clamped to [0, 1] (NaN counts as 0), rounded half up to 8 bits. Contraction
// into fma is off so that the device computes exactly what the CPU reference does.
#pragma OPENCL FP_CONTRACT OFF

inline float composite_weight(float a) {
  return a > 0.0f ? (a < 1.0f ? a : 1.0f) : 0.0f;
}

__kernel void composite_rgb8(__global const uchar* real_rgb, __global const uchar* virtual_rgba,
                             __global const float* alpha, __global uchar* out_rgb, int width,
                             int height) {
  const int x = get_global_id(0);
  const int y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int i = y * width + x;
  const float a = composite_weight(alpha[i]);
  const float3 r = convert_float3(vload3(i, real_rgb));
  const float3 v = convert_float3(vload4(i, virtual_rgba).xyz);
  const float3 c = a * v + (1.0f - a) * r + 0.5f;
  vstore3(convert_uchar3_sat_rtz(c), i, out_rgb);
}

// The matte as an 8-bit image for file output: round(a * 255), half up.
__kernel void matte_gray8(__global const float* alpha, __global uchar* out, int width, int height) {
  const int x = get_global_id(0);
  const int y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int i = y * width + x;
  out[i] = convert_uchar_sat_rtz(composite_weight(alpha[i]) * 255.0f + 0.5f);
}
