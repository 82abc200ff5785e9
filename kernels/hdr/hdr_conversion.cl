// HDR conversion of one raw fisheye frame (kernels/hdr/hdr_conversion.hpp; docs/lighting.md).
// Flags are integer tests on raw - black; the circle test and the scaling are single float
// operations, and contraction is off so the CPU reference reproduces them bit for bit.
// Each work-item converts 4 neighbouring pixels of a row with explicit vector code (vload of
// the 12 interleaved channels, selects instead of branches): 2-2.5x faster on PoCL than one
// pixel per work-item with ifs (docs/performance.md "Light capture"). The last item of a row
// whose width is not a multiple of 4 falls back to the scalar path.
#pragma OPENCL FP_CONTRACT OFF

#define MIN_USABLE_QUALITY 1e-6f  // kMinUsableQuality

// One pixel: the flags and the hat follow the highest channel.
inline float4 convert_one(int r, int g, int b, int x, int y, int saturated_signal, int black_margin,
                          float radiance_scale, float inv_range, int crop, float circle_cx,
                          float circle_cy, float circle_radius2) {
  const int peak = max(r, max(g, b));
  const float dx = (float)x - circle_cx;
  const float dy = (float)y - circle_cy;
  const float d2 = dx * dx + dy * dy;
  const int usable =
      (peak < saturated_signal) & (peak > black_margin) & ((crop == 0) | (d2 <= circle_radius2));
  const float level = (float)peak * inv_range;
  const float hat = max(2.0f * min(level, 1.0f - level), MIN_USABLE_QUALITY);
  return (float4)((float)max(r, 0) * radiance_scale, (float)max(g, 0) * radiance_scale,
                  (float)max(b, 0) * radiance_scale, usable ? hat : 0.0f);
}

__kernel void hdr_conversion(__global const ushort* raw, __global float* out, int width, int height,
                             int black_level, int saturated_signal, int black_margin,
                             float radiance_scale, float inv_range, int crop, float circle_cx,
                             float circle_cy, float circle_radius2) {
  const int x0 = 4 * get_global_id(0);
  const int y = get_global_id(1);
  if (x0 >= width || y >= height) return;
  const int i0 = y * width + x0;
  if (x0 + 4 <= width) {
    const int8 a = convert_int8(vload8(0, raw + 3 * i0)) - black_level;
    const int4 c = convert_int4(vload4(0, raw + 3 * i0 + 8)) - black_level;
    const int4 r = (int4)(a.s0, a.s3, a.s6, c.s1);
    const int4 g = (int4)(a.s1, a.s4, a.s7, c.s2);
    const int4 b = (int4)(a.s2, a.s5, c.s0, c.s3);
    const int4 peak = max(r, max(g, b));
    const float4 dx =
        (float4)((float)x0, (float)(x0 + 1), (float)(x0 + 2), (float)(x0 + 3)) - circle_cx;
    const float dy = (float)y - circle_cy;
    const float4 d2 = dx * dx + dy * dy;
    // Vector comparisons give -1 (all bits) for true, which select() tests; keep it so.
    const int4 inside = crop ? (d2 <= circle_radius2) : (int4)(-1);
    const int4 usable = (peak < saturated_signal) & (peak > black_margin) & inside;
    const float4 level = convert_float4(peak) * inv_range;
    const float4 hat = max(2.0f * min(level, 1.0f - level), MIN_USABLE_QUALITY);
    const float4 q = select((float4)(0.0f), hat, usable);
    const float4 fr = convert_float4(max(r, 0)) * radiance_scale;
    const float4 fg = convert_float4(max(g, 0)) * radiance_scale;
    const float4 fb = convert_float4(max(b, 0)) * radiance_scale;
    vstore16((float16)(fr.s0, fg.s0, fb.s0, q.s0, fr.s1, fg.s1, fb.s1, q.s1, fr.s2, fg.s2, fb.s2,
                       q.s2, fr.s3, fg.s3, fb.s3, q.s3),
             0, out + 4 * i0);
  } else {
    for (int x = x0; x < width; ++x) {
      const int i = y * width + x;
      vstore4(convert_one((int)raw[3 * i] - black_level, (int)raw[3 * i + 1] - black_level,
                          (int)raw[3 * i + 2] - black_level, x, y, saturated_signal, black_margin,
                          radiance_scale, inv_range, crop, circle_cx, circle_cy, circle_radius2),
              0, out + 4 * i);
    }
  }
}
