// Foreground colour at fractional alpha (foreground_estimate_reference.hpp has the method and
// its sources). One work-item per pixel; only fractional pixels on the object read their
// window, the rest copy their colour. The float operations are the reference's, in its order.
#pragma OPENCL FP_CONTRACT OFF

__kernel void foreground_estimate(__global const uchar* colour, __global const float* virtual_mm,
                                  __global const float* visibility, __constant float* decode,
                                  __global uchar* out, int w, int h, int radius, float lo, float hi,
                                  float inv_gamma) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const float vis = visibility[i];
  uchar3 result = vload3(i, colour);
  if (virtual_mm[i] > 0.0f && vis > 0.0f && vis < 1.0f) {
    float3 f = (float3)(0.0f), b = (float3)(0.0f);
    float wf = 0.0f, wb = 0.0f;
    for (int dy = -radius; dy <= radius; ++dy) {
      const int yy = y + dy;
      if (yy < 0 || yy >= h) continue;
      for (int dx = -radius; dx <= radius; ++dx) {
        const int xx = x + dx;
        const int j = yy * w + xx;
        if (xx < 0 || xx >= w || !(virtual_mm[j] > 0.0f)) continue;
        const float v = visibility[j];
        const bool is_f = v <= lo, is_b = v >= hi;
        if (!is_f && !is_b) continue;
        const float wt = 1.0f / (1.0f + (float)(dx * dx + dy * dy));
        const uchar3 c = vload3(j, colour);
        const float3 lin = (float3)(decode[c.x], decode[c.y], decode[c.z]);
        if (is_f) {
          f += wt * lin;
          wf += wt;
        } else {
          b += wt * lin;
          wb += wt;
        }
      }
    }
    if (wf != 0.0f && wb != 0.0f) {
      const float a = 1.0f - vis, na = 1.0f - a;
      const float k = a / (a * a + na * na);
      const float3 fl = f / wf, bl = b / wb;
      const uchar3 c = result;
      const float3 obs = (float3)(decode[c.x], decode[c.y], decode[c.z]);
      const float3 r = obs - a * fl - na * bl;
      const float3 fc = clamp(fl + k * r, 0.0f, 1.0f);
      result = convert_uchar3(floor(255.0f * powr(fc, (float3)(inv_gamma)) + 0.5f));
    }
  }
  vstore3(result, i, out);
}
