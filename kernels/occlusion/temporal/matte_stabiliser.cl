// Temporal stabilisation of the matte (matte_stabiliser.hpp, docs/occlusion.md "Temporal
// stabilisation"); matte_stabiliser_reference.cpp is the specification, operation for operation.
// Per pixel on the object: re-project it into the previous frame with its depth (the real
// depth, else the virtual object's), compare colour and depth there, and blend the previous
// (stabilised) matte in by a weight that falls to 0 where they changed.
//
// Layout (the row-streaming form of the CVF kernels): one work-item walks a strip of rows in
// vectors of 16 pixels, every test a lane mask instead of a branch. One work-item per pixel
// with early returns ran as scalar code on PoCL (its work-item loop was not vectorised:
// "instruction return type cannot be vectorized"), 8.8 CPU-ms a 640x480 frame against 2.4
// now; docs/occlusion.md "Temporal stabilisation" has the measurements.
//
// The history is this kernel's own output, not copies of the inputs: per pixel one 8-byte
// texel (the stabilised matte's float bits; r, g, b and an on-object flag in the high word) and
// the real depth, written to the other of two buffers (the host swaps them). A bilinear tap is
// one 8-byte load instead of five, and the nearest pixel's on-object flag is one of the four
// taps'. Blocks of 16 pixels without the object load nothing but the virtual depth.
// Contraction into fma is off so that the device computes what the CPU reference does.
#pragma OPENCL FP_CONTRACT OFF

typedef struct {
  float r[9];  // row-major rotation, current camera -> previous camera
  float t[3];  // mm
  float fx, fy, cx, cy;
  float history_weight, colour_range, depth_tol_mm, depth_tol_rel, snap;
} Motion;

// The shared vector helpers (common/vector16.cl) are prepended by the host; the history's
// 8-byte texels are stored 16 at a time through this type.
typedef ulong16 __attribute__((aligned(8))) ul16_unaligned;
#define STOREHIST(p, v) (*(__global ul16_unaligned*)(p) = (v))

#define ON_OBJECT (1u << 24)
#define GATHER16(p, i)                                                                     \
  (p[(i).s0], p[(i).s1], p[(i).s2], p[(i).s3], p[(i).s4], p[(i).s5], p[(i).s6], p[(i).s7], \
   p[(i).s8], p[(i).s9], p[(i).sa], p[(i).sb], p[(i).sc], p[(i).sd], p[(i).se], p[(i).sf])

// One bilinear tap of the previous frame for 16 pixels, counted only where it held the object
// (the reference's order of additions; a tap it skips adds exact zeros here).
inline void tap(ulong16 texel, vf wt, vf* sw, vf* sa, vf* sr, vf* sg, vf* sb, vi* on) {
  const uint16 lo = convert_uint16(texel), hi = convert_uint16(texel >> 32);
  *on = (hi & ON_OBJECT) != 0;
  wt = select((vf)(0.0f), wt, *on);
  *sw += wt;
  *sa += select((vf)(0.0f), wt * as_float16(lo), *on);
  *sr += wt * convert_float16(hi & 0xffu);
  *sg += wt * convert_float16((hi >> 8) & 0xffu);
  *sb += wt * convert_float16((hi >> 16) & 0xffu);
}

// The stabilised matte of 16 pixels from (x0, y); `on`: lanes on the object (and in the row).
inline vf stabilise16(int x0, int y, int width, int height, vf a, vf v, vi on, vf dz, vf r, vf g,
                      vf b, __global const ulong* prev_hist, __global const ushort* prev_depth,
                      const Motion* m) {
  const vf xf = convert_float16(x0 + lanes());
  const vi has_d = dz > 0.0f;
  const vf z = select(v, dz, has_d);
  const vf px = (xf - m->cx) / m->fx * z;
  const vf py = ((float)y - m->cy) / m->fy * z;
  const vf qx = m->r[0] * px + m->r[1] * py + m->r[2] * z + m->t[0];
  const vf qy = m->r[3] * px + m->r[4] * py + m->r[5] * z + m->t[1];
  const vf qz = m->r[6] * px + m->r[7] * py + m->r[8] * z + m->t[2];
  // A near occluder's pixels (NEAR_MM: no depth, hole_core_reference.hpp) move with the
  // occluder, not with the scene: compared with the same pixel of the previous frame, which
  // must have been the near occluder too.
  const vi marked = has_d & (dz == (vf)(NEAR_MM));
  vi ok = on & ((qz > 0.0f) | marked);
  vf u = select(m->fx * qx / qz + m->cx, xf, marked);
  vf w = select(m->fy * qy / qz + m->cy, (vf)((float)y), marked);
  ok &= (u >= 0.0f) & (w >= 0.0f) & (u <= (float)(width - 1)) & (w <= (float)(height - 1));
  if (!any(ok)) return a;
  u = select((vf)(0.0f), u, ok);  // lanes that take nothing read pixel 0
  w = select((vf)(0.0f), w, ok);
  const vi x0s = min(convert_int16(u), max(width - 2, 0));
  const vi y0s = min(convert_int16(w), max(height - 2, 0));
  const vi x1s = min(x0s + 1, width - 1), y1s = min(y0s + 1, height - 1);
  const vf fu = u - convert_float16(x0s), fw = w - convert_float16(y0s);
  const vi r0 = y0s * width, r1 = y1s * width;
  const ulong16 t00 = (ulong16)GATHER16(prev_hist, r0 + x0s);
  const ulong16 t10 = (ulong16)GATHER16(prev_hist, r0 + x1s);
  const ulong16 t01 = (ulong16)GATHER16(prev_hist, r1 + x0s);
  const ulong16 t11 = (ulong16)GATHER16(prev_hist, r1 + x1s);
  vf sw = 0.0f, sa = 0.0f, sr = 0.0f, sg = 0.0f, sb = 0.0f;
  vi on00, on10, on01, on11;
  tap(t00, (1.0f - fu) * (1.0f - fw), &sw, &sa, &sr, &sg, &sb, &on00);
  tap(t10, fu * (1.0f - fw), &sw, &sa, &sr, &sg, &sb, &on10);
  tap(t01, (1.0f - fu) * fw, &sw, &sa, &sr, &sg, &sb, &on01);
  tap(t11, fu * fw, &sw, &sa, &sr, &sg, &sb, &on11);
  // The nearest previous pixel is one of the four taps: no object there then, its matte says
  // nothing; a changed depth there is another surface.
  const vi ju = convert_int16(u + 0.5f), jw = convert_int16(w + 0.5f);
  const vi right = ju != x0s, below = jw != y0s;
  ok &= select(select(on00, on10, right), select(on01, on11, right), below);
  const vf dp = convert_float16((ushort16)GATHER16(prev_depth, jw * width + ju));
  ok &=
      ~(has_d & ~marked & (dp > 0.0f) & (fabs(qz - dp) > m->depth_tol_mm + m->depth_tol_rel * qz));
  ok &= ~marked | (dp == (vf)(NEAR_MM));
  ok &= (sw > 1e-6f);
  const vf dr = (sr / sw - r) / 255.0f, dg = (sg / sw - g) / 255.0f, db = (sb / sw - b) / 255.0f;
  // Depth measured in one frame only: it cannot confirm the surface, so colour must, closer.
  const vf range = select((vf)(m->colour_range), (vf)(UNCONFIRMED_RANGE), has_d ^ (dp > 0.0f));
  const vf c = (dr * dr + dg * dg + db * db) / (range * range);
  ok &= (c < 1.0f);
  // Heavier where depth confirms the surface in both frames; on a near occluder the history
  // may only hide more (matte_stabiliser_params.hpp says why and what was measured).
  const vi confirmed = has_d & ~marked & (dp > 0.0f);
  const vf weight = select(select((vf)(m->history_weight), (vf)(CONFIRMED_WEIGHT), confirmed),
                           (vf)(NEAR_WEIGHT), marked);
  const vf h = weight * (1.0f - c);
  vf out = (1.0f - h) * a + h * (sa / sw);
  out = select(out, fmin(out, a), marked);
  out = select(out, (vf)(0.0f), out < m->snap);
  out = select(out, (vf)(1.0f), out > 1.0f - m->snap);
  return select(a, out, ok);
}

inline ulong16 texels(vf alpha, vf r, vf g, vf b, vi on) {
  const uint16 hi = convert_uint16(r) | convert_uint16(g) << 8 | convert_uint16(b) << 16 |
                    select((uint16)(0u), (uint16)(ON_OBJECT), on);
  return convert_ulong16(as_uint16(alpha)) | convert_ulong16(hi) << 32;
}

// In place: each pixel of `alpha` is read and written by one lane only; the history is read
// from prev_* and written to next_* (two buffers). Without a previous frame only the history
// is written. Rows [first_row, end_row) only: the host keeps the others free of the object.
__kernel void stabilise_matte(__global float* alpha, __global const uchar* colour,
                              __global const ushort* real_depth, __global const float* virt,
                              __global const ulong* prev_hist, __global const ushort* prev_depth,
                              __global ulong* next_hist, __global ushort* next_depth, int width,
                              int height, int first_row, int end_row, int strip_rows,
                              int have_previous, Motion m) {
  const int y_begin = first_row + (int)get_global_id(1) * strip_rows;
  const int y_end = min(y_begin + strip_rows, end_row);
  for (int y = y_begin; y < y_end; ++y) {
    const int row = y * width;
    for (int x0 = 0; x0 < width; x0 += VW) {
      const int i = row + x0;
      const bool full = x0 + VW <= width;
      const vi in_row = x0 + lanes() < width;
      vf v;
      if (full) {
        v = LOADF(virt + i);
      } else {
        float t[VW];
        for (int k = 0; k < VW; ++k) t[k] = x0 + k < width ? virt[i + k] : 0.0f;
        v = vload16(0, t);
      }
      const vi on = in_row & (v > 0.0f);
      if (!any(on)) {  // nothing of the object: the history says so, the matte is kept
        if (full) {
          STOREHIST(next_hist + i, (ulong16)(0));
        } else {
          for (int k = 0; x0 + k < width; ++k) next_hist[i + k] = 0;
        }
        continue;
      }
      vf a, r, g, b, d;
      if (full) {
        a = LOADF(alpha + i);
        load_rgb16(colour + 3 * i, &r, &g, &b);
        d = convert_float16(LOADU16(real_depth + i));
      } else {
        float ta[VW], tr[VW], tg[VW], tb[VW], td[VW];
        for (int k = 0; k < VW; ++k) {
          const bool in = x0 + k < width;
          ta[k] = in ? alpha[i + k] : 0.0f;
          tr[k] = in ? (float)colour[3 * (i + k)] : 0.0f;
          tg[k] = in ? (float)colour[3 * (i + k) + 1] : 0.0f;
          tb[k] = in ? (float)colour[3 * (i + k) + 2] : 0.0f;
          td[k] = in ? (float)real_depth[i + k] : 0.0f;
        }
        a = vload16(0, ta);
        r = vload16(0, tr);
        g = vload16(0, tg);
        b = vload16(0, tb);
        d = vload16(0, td);
      }
      const vf out = have_previous ? stabilise16(x0, y, width, height, a, v, on, d, r, g, b,
                                                 prev_hist, prev_depth, &m)
                                   : a;
      const ulong16 hist = texels(out, r, g, b, on);
      if (full) {
        STOREF(alpha + i, out);
        STOREHIST(next_hist + i, hist);
        STOREU16(next_depth + i, convert_ushort16(d));
      } else {
        float to[VW];
        ulong th[VW];
        vstore16(out, 0, to);
        vstore16(hist, 0, th);
        for (int k = 0; x0 + k < width; ++k) {
          alpha[i + k] = to[k];
          next_hist[i + k] = th[k];
          next_depth[i + k] = real_depth[i + k];
        }
      }
    }
  }
}
