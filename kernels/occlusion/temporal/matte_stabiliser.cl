// Temporal stabilisation of the matte (matte_stabiliser.hpp, docs/occlusion.md "Temporal
// stabilisation"). One work-item per pixel: re-project the pixel into the previous frame with
// its depth (the real depth, else the virtual object's), compare colour and depth there, and
// blend the previous (stabilised) matte in by a weight that falls to 0 where they changed.
// Contraction into fma is off so that the device computes what the CPU reference does.
#pragma OPENCL FP_CONTRACT OFF

typedef struct {
  float r[9];  // row-major rotation, current camera -> previous camera
  float t[3];  // mm
  float fx, fy, cx, cy;
  float history_weight, colour_range, depth_tol_mm, depth_tol_rel;
} Motion;

// In place: each work-item reads and writes only its own pixel of `alpha`.
// One bilinear tap of the previous frame, counted only where it held the object (the same
// order of additions as the reference's loop).
inline void tap(__global const float* prev_alpha, __global const uchar* prev_colour,
                __global const float* prev_virt, int t, float wt, float4* acc, float* sw) {
  if (!(prev_virt[t] > 0.0f)) return;
  *sw += wt;
  *acc += wt * (float4)(prev_alpha[t], (float)prev_colour[3 * t], (float)prev_colour[3 * t + 1],
                        (float)prev_colour[3 * t + 2]);
}

__kernel void stabilise_matte(__global float* alpha, __global const uchar* colour,
                              __global const ushort* real_depth, __global const float* virt,
                              __global const float* prev_alpha, __global const uchar* prev_colour,
                              __global const ushort* prev_depth, __global const float* prev_virt,
                              int width, int height, Motion m) {
  const int x = get_global_id(0);
  const int y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int i = y * width + x;
  const float a = alpha[i];
  const float v = virt[i];
  if (!(v > 0.0f)) return;
  const ushort d = real_depth[i];
  const float z = d > 0 ? (float)d : v;
  const float px = ((float)x - m.cx) / m.fx * z, py = ((float)y - m.cy) / m.fy * z;
  const float qx = m.r[0] * px + m.r[1] * py + m.r[2] * z + m.t[0];
  const float qy = m.r[3] * px + m.r[4] * py + m.r[5] * z + m.t[1];
  const float qz = m.r[6] * px + m.r[7] * py + m.r[8] * z + m.t[2];
  if (!(qz > 0.0f)) return;
  const float u = m.fx * qx / qz + m.cx, w = m.fy * qy / qz + m.cy;
  if (!(u >= 0.0f && w >= 0.0f && u <= (float)(width - 1) && w <= (float)(height - 1))) return;
  // Depth at the nearest previous pixel: a changed surface is not the same point.
  const int j = (int)(w + 0.5f) * width + (int)(u + 0.5f);
  if (!(prev_virt[j] > 0.0f)) return;  // no object there then: its matte says nothing
  const ushort dp = prev_depth[j];
  if (d > 0 && dp > 0 && fabs(qz - (float)dp) > m.depth_tol_mm + m.depth_tol_rel * qz) return;
  // Bilinear colour and matte over the taps that held the object.
  const int x0 = min((int)u, max(width - 2, 0)), y0 = min((int)w, max(height - 2, 0));
  const int x1 = min(x0 + 1, width - 1), y1 = min(y0 + 1, height - 1);
  const float fu = u - (float)x0, fw = w - (float)y0;
  float4 acc = (float4)(0.0f);  // matte, r, g, b, weighted
  float sw = 0.0f;
  tap(prev_alpha, prev_colour, prev_virt, y0 * width + x0, (1.0f - fu) * (1.0f - fw), &acc, &sw);
  tap(prev_alpha, prev_colour, prev_virt, y0 * width + x1, fu * (1.0f - fw), &acc, &sw);
  tap(prev_alpha, prev_colour, prev_virt, y1 * width + x0, (1.0f - fu) * fw, &acc, &sw);
  tap(prev_alpha, prev_colour, prev_virt, y1 * width + x1, fu * fw, &acc, &sw);
  const float sa = acc.x, sr = acc.y, sg = acc.z, sb = acc.w;
  if (!(sw > 1e-6f)) return;
  const float dr = (sr / sw - (float)colour[3 * i]) / 255.0f;
  const float dg = (sg / sw - (float)colour[3 * i + 1]) / 255.0f;
  const float db = (sb / sw - (float)colour[3 * i + 2]) / 255.0f;
  const float c = (dr * dr + dg * dg + db * db) / (m.colour_range * m.colour_range);
  if (!(c < 1.0f)) return;
  const float h = m.history_weight * (1.0f - c);
  alpha[i] = (1.0f - h) * a + h * (sa / sw);
}
