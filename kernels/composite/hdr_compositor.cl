// HDR compositing (kernels/composite/hdr_compositor.hpp, docs/compositing.md): the real frame
// to radiance through the colour camera's response, the premultiplied virtual layer over it
// through the occlusion matte (differential rendering, Debevec 1998; Walton 2019 ch. 6), and
// back through the same response. Bit-exact with hdr_composite_reference: contraction is off,
// every float operation is the reference's in the same order, and the 8-bit encode counts
// thresholds from tables instead of calling pow.
//
// The host copies the real frame to the output first, and this kernel rewrites only pixels
// whose matte is > 0, usually a small part of the frame. Each work-item walks PIXELS pixels
// and skips the others at the cost of one float load. PoCL does not vectorise this across
// work-items (3-byte pixels, per-channel code and a byte table each defeat its vectoriser,
// and a variant it did vectorise was slower, with gathers), so the 3 channels of a pixel are
// one float4 (docs/performance.md "HDR compositing").
#pragma OPENCL FP_CONTRACT OFF

#ifndef STEPS
#error "build with -DSTEPS=n, CameraCurve::steps() of the gamma in use"
#endif

#define PIXELS 16       // per work-item: HdrCompositor::kPixelsPerItem
#define INDEX_SHIFT 16  // CameraCurve::kIndexShift: 7 mantissa bits, 128 entries per octave

// composite_weight: clamp to [0, 1] with NaN as 0.
inline float weight(float a) {
  return a > 0.0f ? (a < 1.0f ? a : 1.0f) : 0.0f;
}

inline float4 weight4(float4 a) {
  const float4 below_one = select((float4)(1.0f), a, a < 1.0f);  // inf and NaN: 1
  return select((float4)(0.0f), below_one, a > 0.0f);            // NaN and <= 0: 0
}

// CameraCurve::encode_fast on three channels: the entry of x's float bits (sign, exponent, 7
// mantissa bits) holds the threshold count at the entry's start and the next threshold, so
// one load and one compare give the answer; further STEPS only for steep curves.
inline uint3 encode3(float4 x, __global const uint* entries, int index_base, int index_last,
                     __global const float* thresholds) {
  const int4 j = clamp((as_int4(x) >> INDEX_SHIFT) - index_base, 0, index_last);
  const uint2 a = vload2(j.x, entries), b = vload2(j.y, entries), c = vload2(j.z, entries);
  uint3 v = (uint3)(a.x, b.x, c.x);
  v.x += x.x >= as_float(a.y) ? 1u : 0u;
  v.y += x.y >= as_float(b.y) ? 1u : 0u;
  v.z += x.z >= as_float(c.y) ? 1u : 0u;
  for (int k = 1; k < STEPS; ++k) {
    v.x += x.x >= thresholds[v.x + 1] ? 1u : 0u;
    v.y += x.y >= thresholds[v.y + 1] ? 1u : 0u;
    v.z += x.z >= thresholds[v.z + 1] ? 1u : 0u;
  }
  return v;
}

// Pixels [begin, end) of the flattened frame (nothing depends on x or y).
__kernel void hdr_composite(__global const uchar* real_rgb, __global const float* layer,
                            __global const float* matte, __global uchar* out_rgb, int begin,
                            int end_pixel, float4 e,
                            float4 inverse_e, __global const float* decode,
                            __global const float* thresholds, __global const uint* entries,
                            int index_base, int index_last) {
  const int i0 = begin + PIXELS * get_global_id(0);
  if (i0 >= end_pixel) return;
  const int end = min(i0 + PIXELS, end_pixel);
  for (int i = i0; i < end; ++i) {
    const float m_raw = matte[i];
    if (!(m_raw > 0.0f)) continue;  // no virtual layer, or all of it hidden: out = real
    const float m = weight(m_raw);
    const float4 l = vload4(i, layer);
    const float w = m * weight(l.w);
    const uchar3 r8 = vload3(i, real_rgb);
    // hdr_composite_linear's operations per channel (w is the 4th lane's business only).
    const float4 real = e * (float4)(decode[r8.x], decode[r8.y], decode[r8.z], 0.0f);
    const float4 x = weight4((m * l + (1.0f - w) * real) * inverse_e);
    vstore3(convert_uchar3(encode3(x, entries, index_base, index_last, thresholds)), i, out_rgb);
  }
}
