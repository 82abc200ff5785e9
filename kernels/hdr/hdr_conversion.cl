// HDR conversion of one raw fisheye frame (kernels/hdr/hdr_conversion.hpp; docs/lighting.md).
// Flags are integer tests on raw - black; the circle test and the scaling are single float
// operations, and contraction is off so the CPU reference reproduces them bit for bit.
#pragma OPENCL FP_CONTRACT OFF

#define MIN_USABLE_QUALITY 1e-6f  // kMinUsableQuality

__kernel void hdr_conversion(__global const ushort* raw, __global float4* out, int width,
                             int height, int black_level, int saturated_signal, int black_margin,
                             float radiance_scale, float inv_range, int crop, float circle_cx,
                             float circle_cy, float circle_radius2) {
  const int x = get_global_id(0);
  const int y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int i = y * width + x;
  const int r = (int)raw[3 * i + 0] - black_level;
  const int g = (int)raw[3 * i + 1] - black_level;
  const int b = (int)raw[3 * i + 2] - black_level;
  const int peak = max(r, max(g, b));  // the flags and the hat follow the highest channel

  bool usable = peak < saturated_signal && peak > black_margin;
  if (crop) {
    const float dx = (float)x - circle_cx;
    const float dy = (float)y - circle_cy;
    const float d2 = dx * dx + dy * dy;
    usable = usable && d2 <= circle_radius2;
  }
  float quality = 0.0f;
  if (usable) {
    const float level = (float)peak * inv_range;
    quality = max(2.0f * min(level, 1.0f - level), MIN_USABLE_QUALITY);
  }
  out[i] = (float4)((float)max(r, 0) * radiance_scale, (float)max(g, 0) * radiance_scale,
                    (float)max(b, 0) * radiance_scale, quality);
}
