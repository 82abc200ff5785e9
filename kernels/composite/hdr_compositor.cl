// HDR compositing (kernels/composite/hdr_compositor.hpp, docs/compositing.md): the real frame
// to radiance through the colour camera's response, the premultiplied virtual layer over it
// through the occlusion matte (differential rendering, Debevec 1998; Walton 2019 ch. 6), and
// back through the same response. Bit-exact with hdr_composite_reference: contraction is off,
// every float operation is the reference's in the same order, and the 8-bit encode counts
// thresholds from a table instead of calling pow.
// Each work-item takes 4 neighbouring pixels of a row as explicit vectors (the layout of
// kernels/hdr/hdr_conversion.cl, which measured 2-2.5x faster on PoCL than one pixel per
// work-item); a group of 4 whose matte is 0 everywhere copies its bytes and skips the float
// layer, which is most of a frame. The last item of a row whose width is not a multiple of 4
// takes the scalar path.
#pragma OPENCL FP_CONTRACT OFF

#define INDEX_SCALE 4095.0f  // CameraCurve::kIndexSize - 1
#define INDEX_LAST 4095

inline float weight(float a) {
  return a > 0.0f ? (a < 1.0f ? a : 1.0f) : 0.0f;
}

inline float4 weight4(float4 a) {
  return select((float4)(0.0f), min(a, 1.0f), a > 0.0f);  // NaN > 0 is false: 0
}

// CameraCurve::encode_fast: a guess from the sqrt index (never above the answer), then steps.
inline uchar encode(float x, __global const uchar* index, __global const float* thresholds,
                    int steps) {
  x = fmin(fmax(x, 0.0f), 1.0f);
  const int j = min((int)(sqrt(x) * INDEX_SCALE), INDEX_LAST);
  int v = index[j];
  for (int k = 0; k < steps; ++k) v += x >= thresholds[v + 1] ? 1 : 0;
  return (uchar)v;
}

inline int4 encode4(float4 x, __global const uchar* index, __global const float* thresholds,
                    int steps) {
  x = fmin(fmax(x, 0.0f), 1.0f);
  const int4 j = min(convert_int4(sqrt(x) * INDEX_SCALE), INDEX_LAST);
  int4 v = (int4)(index[j.s0], index[j.s1], index[j.s2], index[j.s3]);
  for (int k = 0; k < steps; ++k) {
    const float4 t = (float4)(thresholds[v.s0 + 1], thresholds[v.s1 + 1], thresholds[v.s2 + 1],
                              thresholds[v.s3 + 1]);
    v -= x >= t;  // true is -1 in vector comparisons
  }
  return v;
}

// One channel of one pixel, hdr_composite_linear's operations.
inline float composite_one(float real, float layer, float m, float w, float inverse_e) {
  return (m * layer + (1.0f - w) * real) * inverse_e;
}

__kernel void hdr_composite(__global const uchar* real_rgb, __global const float* layer,
                            __global const float* matte, __global uchar* out_rgb, int width,
                            int height, float4 e, float4 inverse_e, __global const float* decode,
                            __global const float* thresholds, __global const uchar* index,
                            int steps) {
  const int x0 = 4 * get_global_id(0);
  const int y = get_global_id(1);
  if (x0 >= width || y >= height) return;
  const int i0 = y * width + x0;
  if (x0 + 4 <= width) {
    const uchar8 a = vload8(0, real_rgb + 3 * i0);
    const uchar4 b = vload4(0, real_rgb + 3 * i0 + 8);
    const float4 m_raw = vload4(0, matte + i0);
    const int4 visible = m_raw > 0.0f;
    if (!any(visible)) {  // no virtual layer here, or all of it hidden: the frame as it was
      vstore8(a, 0, out_rgb + 3 * i0);
      vstore4(b, 0, out_rgb + 3 * i0 + 8);
      return;
    }
    const int4 r8 = (int4)(a.s0, a.s3, a.s6, b.s1);
    const int4 g8 = (int4)(a.s1, a.s4, a.s7, b.s2);
    const int4 b8 = (int4)(a.s2, a.s5, b.s0, b.s3);
    const float16 l = vload16(0, layer + 4 * i0);
    const float4 m = weight4(m_raw);
    const float4 w = m * weight4(l.s37bf);
    const float4 one_minus_w = 1.0f - w;
    const float4 rr = e.x * (float4)(decode[r8.s0], decode[r8.s1], decode[r8.s2], decode[r8.s3]);
    const float4 rg = e.y * (float4)(decode[g8.s0], decode[g8.s1], decode[g8.s2], decode[g8.s3]);
    const float4 rb = e.z * (float4)(decode[b8.s0], decode[b8.s1], decode[b8.s2], decode[b8.s3]);
    const int4 o_r = select(
        r8, encode4((m * l.s048c + one_minus_w * rr) * inverse_e.x, index, thresholds, steps),
        visible);
    const int4 o_g = select(
        g8, encode4((m * l.s159d + one_minus_w * rg) * inverse_e.y, index, thresholds, steps),
        visible);
    const int4 o_b = select(
        b8, encode4((m * l.s26ae + one_minus_w * rb) * inverse_e.z, index, thresholds, steps),
        visible);
    vstore8(convert_uchar8((int8)(o_r.s0, o_g.s0, o_b.s0, o_r.s1, o_g.s1, o_b.s1, o_r.s2, o_g.s2)),
            0, out_rgb + 3 * i0);
    vstore4(convert_uchar4((int4)(o_b.s2, o_r.s3, o_g.s3, o_b.s3)), 0, out_rgb + 3 * i0 + 8);
  } else {
    for (int x = x0; x < width; ++x) {
      const int i = y * width + x;
      const float m_raw = matte[i];
      if (!(m_raw > 0.0f)) {
        for (int c = 0; c < 3; ++c) out_rgb[3 * i + c] = real_rgb[3 * i + c];
        continue;
      }
      const float4 l = vload4(i, layer);
      const float m = weight(m_raw);
      const float w = m * weight(l.w);
      out_rgb[3 * i] = encode(composite_one(e.x * decode[real_rgb[3 * i]], l.x, m, w, inverse_e.x),
                              index, thresholds, steps);
      out_rgb[3 * i + 1] =
          encode(composite_one(e.y * decode[real_rgb[3 * i + 1]], l.y, m, w, inverse_e.y), index,
                 thresholds, steps);
      out_rgb[3 * i + 2] =
          encode(composite_one(e.z * decode[real_rgb[3 * i + 2]], l.z, m, w, inverse_e.z), index,
                 thresholds, steps);
    }
  }
}
