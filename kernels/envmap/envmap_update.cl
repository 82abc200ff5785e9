// Environment-map keyframe update (thesis ch. 6; docs/light-capture.md). Each work-item
// updates 16 neighbouring texels of one row of the n x 6n texel image (face = row / n): their
// world directions (with a room box: the direction from the fisheye's centre to where the
// texel's ray from the keyframe's position leaves the box), rotated into the fisheye's frame,
// projected through the camera's lookup table (fisheye_lut.hpp: indexed by the ideal
// equidistant projection, holding the real model's pixel, so any model works), bilinearly
// sampled, then merged by the selected rule. envmap_update_reference.cpp mirrors every step in
// float, lane by lane.
//
// Why 16 texels per work-item in explicit float16 code, with selects and unconditional loads:
// PoCL 3.1 ran the one-texel-per-work-item version as scalar code (no vectorisation across
// work-items), most of its time waiting for the scattered pixel loads one texel at a time;
// here the 64 pixel loads of 16 texels are independent, so the CPU overlaps their cache
// misses, and the arithmetic runs 16 wide (one AVX-512 register). Per 1024 px frame, in the
// interleaved kernel bench: 1 texel per work-item ~10 CPU-ms, 8 lanes 3.3, 16 lanes 2.2
// (docs/performance.md "Light capture: bench light").
//
// Two entry points differ only in what they sample: envmap_update_raw converts the four raw
// pixels of each footprint with the HDR conversion's own formulas (the program is
// hdr_conversion.cl followed by this file, whose FP_CONTRACT OFF then covers both; convert_lanes
// below is its convert_one lane by lane), so a frame is never converted whole (98k texels
// read ~400k of a 1024 px frame's 1M pixels, and nothing is written back); envmap_update
// samples an already converted image (rgb radiance, a quality, 0 = unusable).
#define RULE_KALMAN 0
#define RULE_BEST_SCORE 1
#define LANES 16
#define INLINE inline __attribute__((always_inline))
// fisheye_lut.hpp's FisheyeLut::kInvalid is -1e6: a real pixel is far above this.
#define LUT_VALID_ABOVE -1.0e5f

// OpenGL cube map face coordinates -> directions (not normalised; core/cubemap.cpp), for 16
// lanes of one row: sc = 2u - 1 per lane, tc = 2v - 1 shared.
INLINE void cube_directions(int face, float16 sc, float tc, float16* dx, float16* dy, float16* dz) {
  const float16 t = (float16)(tc), one = (float16)(1.0f);
  switch (face) {
    case 0:
      *dx = one, *dy = -t, *dz = -sc;
      break;
    case 1:
      *dx = -one, *dy = -t, *dz = sc;
      break;
    case 2:
      *dx = sc, *dy = one, *dz = t;
      break;
    case 3:
      *dx = sc, *dy = -one, *dz = -t;
      break;
    case 4:
      *dx = sc, *dy = -t, *dz = one;
      break;
    default:
      *dx = -sc, *dy = -t, *dz = -one;
      break;
  }
}

// atan2(r, z) for r >= 0, in [0, pi]: Abramowitz & Stegun 4.4.49 (|error| <= 2e-8 rad on
// [0, 1]; 1e-5 px at the sim's 1024 px fisheye) after an octant reduction. PoCL's atan2 took
// 60 % of the scalar kernel's time; envmap_update_reference.cpp evaluates the same polynomial.
INLINE float16 polar_angle(float16 r, float16 z) {
  const float16 az = fabs(z);
  const float16 hi = fmax(r, az), lo = fmin(r, az);
  const float16 x = select((float16)(0.0f), lo / hi, hi > 0.0f), x2 = x * x;
  float16 a =
      x *
      (1.0f + x2 * (-0.3333314528f +
                    x2 * (0.1999355085f +
                          x2 * (-0.1420889944f +
                                x2 * (0.1065626393f +
                                      x2 * (-0.0752896400f +
                                            x2 * (0.0429096138f +
                                                  x2 * (-0.0161657367f + x2 * 0.0028662257f))))))));
  a = select(a, M_PI_2_F - a, r > az);
  return select(a, M_PI_F - a, z < 0.0f);
}

// Whether no texel x0 .. x0 + 15 of `row` can be in the fisheye's table: the group's texel
// directions lie on a straight segment d(s) = base + s e of a cube face (e a unit axis
// orthogonal to base, as cube_directions), so the cosine of their angle to the optical axis,
// (alpha + beta s) / sqrt(gamma + s^2), has one extremum, at s = beta gamma / alpha: its
// largest value over the group is at an end or there. `cos_limit` is the cosine of the table's
// max_theta widened by the parallax's bound and a margin (EnvmapUpdate::cull_cos); below -1 it
// never culls. Conservative: a group it keeps may be unseen; one it culls has no lane in the
// table. About half the cube lies below an upward fisheye's horizon; those groups skipped the
// image loads but still paid the directions and the table reads before (issue #19's budget).
INLINE bool group_hidden(int n, int row, int x0, float4 axis, float cos_limit) {
  if (cos_limit < -1.0f) return false;
  const int face = row / n, y = row - face * n;
  const float inv_n = 1.0f / (float)n;
  const float t = 2.0f * (((float)y + 0.5f) * inv_n) - 1.0f;
  const float s0 = 2.0f * (((float)x0 + 0.5f) * inv_n) - 1.0f;
  const float s1 = 2.0f * (((float)min(x0 + LANES - 1, n - 1) + 0.5f) * inv_n) - 1.0f;
  float3 base, e;
  switch (face) {
    case 0:
      base = (float3)(1.0f, -t, 0.0f), e = (float3)(0.0f, 0.0f, -1.0f);
      break;
    case 1:
      base = (float3)(-1.0f, -t, 0.0f), e = (float3)(0.0f, 0.0f, 1.0f);
      break;
    case 2:
      base = (float3)(0.0f, 1.0f, t), e = (float3)(1.0f, 0.0f, 0.0f);
      break;
    case 3:
      base = (float3)(0.0f, -1.0f, -t), e = (float3)(1.0f, 0.0f, 0.0f);
      break;
    case 4:
      base = (float3)(0.0f, -t, 1.0f), e = (float3)(1.0f, 0.0f, 0.0f);
      break;
    default:
      base = (float3)(0.0f, -t, -1.0f), e = (float3)(-1.0f, 0.0f, 0.0f);
      break;
  }
  const float alpha = dot(axis.xyz, base), beta = dot(axis.xyz, e), gamma = dot(base, base);
  float best = fmax((alpha + beta * s0) * rsqrt(gamma + s0 * s0),
                    (alpha + beta * s1) * rsqrt(gamma + s1 * s1));
  if (alpha != 0.0f) {
    const float s = beta * gamma / alpha;
    if (s > s0 && s < s1) best = fmax(best, (alpha + beta * s) * rsqrt(gamma + s * s));
  }
  return best < cos_limit;
}

// The geometry of the 16 texels x0 .. x0 + 15 of `row`: the top-left pixel of each bilinear
// footprint (pixel centres on integers) and its weights. Returns the lanes the fisheye sees
// (the four table cells around the direction valid, footprint inside the image, x < n); other
// lanes get footprint (0, 0), so that every load stays inside the image.
INLINE int16 footprints(int n, int row, int x0, float4 r0, float4 r1, float4 r2,
                        __global const float2* lut, int lut_size, float lut_centre, float lut_scale,
                        float lut_max_theta, int parallax, float4 box_lo, float4 box_hi,
                        float4 offset, int width, int height, int16* px, int16* py, float16* ax,
                        float16* ay) {
  const int face = row / n, y = row - face * n;
  const float inv_n = 1.0f / (float)n;
  const float16 xs =
      (float16)((float)x0) + (float16)(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f, 8.0f, 9.0f,
                                       10.0f, 11.0f, 12.0f, 13.0f, 14.0f, 15.0f);
  const float16 sc = 2.0f * ((xs + 0.5f) * inv_n) - 1.0f;
  const float tc = 2.0f * (((float)y + 0.5f) * inv_n) - 1.0f;
  float16 dx, dy, dz;
  cube_directions(face, sc, tc, &dx, &dy, &dz);
  float16 wx = dx, wy = dy, wz = dz;
  if (parallax) {
    // Exit of the ray k + t d from the box (box_lo, box_hi relative to k; k inside, so every
    // axis gives t >= 0 or +inf (NaN for 0 / 0, which fmax drops), the major axis a finite
    // one); then the wall point seen from the fisheye: (k - c) + t d. envmap_types.cpp's
    // box_exit / parallax_direction.
    const float16 tx = fmax(box_lo.x / dx, box_hi.x / dx);
    const float16 ty = fmax(box_lo.y / dy, box_hi.y / dy);
    const float16 tz = fmax(box_lo.z / dz, box_hi.z / dz);
    const float16 t = fmin(tx, fmin(ty, tz));
    wx = offset.x + t * dx;
    wy = offset.y + t * dy;
    wz = offset.z + t * dz;
  }
  const float16 cx = r0.x * wx + r0.y * wy + r0.z * wz;
  const float16 cy = r1.x * wx + r1.y * wy + r1.z * wz;
  const float16 cz = r2.x * wx + r2.y * wy + r2.z * wz;
  // The ideal equidistant projection into the table (fisheye_lut.hpp); on the axis (r = 0)
  // the table's centre, straight back nothing.
  const float16 r = sqrt(cx * cx + cy * cy);
  const float16 theta = polar_angle(r, cz);
  const float16 s = lut_scale * theta / r;
  const int16 on_axis = r == 0.0f;
  const float16 gx = select(lut_centre + s * cx, (float16)(lut_centre), on_axis);
  const float16 gy = select(lut_centre + s * cy, (float16)(lut_centre), on_axis);
  const float16 gx0 = floor(gx), gy0 = floor(gy);
  const int16 in_table = (theta <= lut_max_theta) & (~on_axis | (cz > 0.0f)) & (gx0 >= 0.0f) &
                         (gy0 >= 0.0f) & (gx0 + 1.0f < (float)lut_size) &
                         (gy0 + 1.0f < (float)lut_size);
  // Lanes outside the table may hold NaN or huge values: zero them before the conversion.
  const int16 ga = convert_int16(select((float16)(0.0f), gy0, in_table)) * lut_size +
                   convert_int16(select((float16)(0.0f), gx0, in_table));
  float16 ua, va, ub, vb, uc, vc, ud, vd;
#define LUT_LANE(j)                                                            \
  {                                                                            \
    const float2 a = lut[ga.s##j], b = lut[ga.s##j + 1];                       \
    const float2 c = lut[ga.s##j + lut_size], d = lut[ga.s##j + lut_size + 1]; \
    ua.s##j = a.x, va.s##j = a.y, ub.s##j = b.x, vb.s##j = b.y;                \
    uc.s##j = c.x, vc.s##j = c.y, ud.s##j = d.x, vd.s##j = d.y;                \
  }
  LUT_LANE(0)
  LUT_LANE(1)
  LUT_LANE(2)
  LUT_LANE(3)
  LUT_LANE(4)
  LUT_LANE(5)
  LUT_LANE(6)
  LUT_LANE(7)
  LUT_LANE(8)
  LUT_LANE(9)
  LUT_LANE(a)
  LUT_LANE(b)
  LUT_LANE(c)
  LUT_LANE(d)
  LUT_LANE(e)
  LUT_LANE(f)
#undef LUT_LANE
  const int16 cells_valid = (ua > LUT_VALID_ABOVE) & (ub > LUT_VALID_ABOVE) &
                            (uc > LUT_VALID_ABOVE) & (ud > LUT_VALID_ABOVE);
  const float16 bx = gx - gx0, by = gy - gy0;
  const float16 u = (ua + bx * (ub - ua)) + by * ((uc + bx * (ud - uc)) - (ua + bx * (ub - ua)));
  const float16 v = (va + bx * (vb - va)) + by * ((vc + bx * (vd - vc)) - (va + bx * (vb - va)));
  const float16 fx0 = floor(u), fy0 = floor(v);
  const int16 lane = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const int16 seen = in_table & cells_valid & (fx0 >= 0.0f) & (fy0 >= 0.0f) &
                     (fx0 + 1.0f < (float)width) & (fy0 + 1.0f < (float)height) & (lane < n - x0);
  // Unseen lanes may hold NaN or huge values: zero them before the conversion to int.
  *px = convert_int16(select((float16)(0.0f), fx0, seen));
  *py = convert_int16(select((float16)(0.0f), fy0, seen));
  *ax = u - fx0;
  *ay = v - fy0;
  return seen;
}

// The HDR conversion of 16 pixels (hdr_conversion.cl's convert_one, lane by lane): r, g, b
// are raw - black. Writes radiance and quality (0 = unusable).
INLINE void convert_lanes(int16 r, int16 g, int16 b, int16 x, int16 y, int saturated_signal,
                          int black_margin, float radiance_scale, float inv_range, int crop,
                          float circle_cx, float circle_cy, float circle_radius2, float16* R,
                          float16* G, float16* B, float16* Q) {
  const int16 peak = max(r, max(g, b));
  const float16 dx = convert_float16(x) - circle_cx;
  const float16 dy = convert_float16(y) - circle_cy;
  const float16 d2 = dx * dx + dy * dy;
  const int16 inside = crop ? (d2 <= circle_radius2) : (int16)(-1);
  const int16 usable = (peak < saturated_signal) & (peak > black_margin) & inside;
  const float16 level = convert_float16(peak) * inv_range;
  const float16 hat = max(2.0f * min(level, 1.0f - level), MIN_USABLE_QUALITY);
  *Q = select((float16)(0.0f), hat, usable);
  *R = convert_float16(max(r, 0)) * radiance_scale;
  *G = convert_float16(max(g, 0)) * radiance_scale;
  *B = convert_float16(max(b, 0)) * radiance_scale;
}

INLINE float16 luminance_lanes(float16 r, float16 g, float16 b) {
  return 0.2126f * r + 0.7152f * g + 0.0722f * b;
}

// Texels x0 .. x0 + count - 1 (count <= 16) of a float4 image as four float16 channels.
INLINE void load_texels(__global const float4* p, int count, float16* r, float16* g, float16* b,
                        float16* w) {
  float16 q0, q1, q2, q3;
  if (count == LANES) {
    q0 = vload16(0, (__global const float*)p);
    q1 = vload16(1, (__global const float*)p);
    q2 = vload16(2, (__global const float*)p);
    q3 = vload16(3, (__global const float*)p);
  } else {
    float v[4 * LANES];
    for (int i = 0; i < 4 * LANES; ++i) v[i] = 0.0f;
    for (int j = 0; j < count; ++j) vstore4(p[j], j, v);
    q0 = vload16(0, v);
    q1 = vload16(1, v);
    q2 = vload16(2, v);
    q3 = vload16(3, v);
  }
  *r = (float16)(q0.s048c, q1.s048c, q2.s048c, q3.s048c);
  *g = (float16)(q0.s159d, q1.s159d, q2.s159d, q3.s159d);
  *b = (float16)(q0.s26ae, q1.s26ae, q2.s26ae, q3.s26ae);
  *w = (float16)(q0.s37bf, q1.s37bf, q2.s37bf, q3.s37bf);
}

#define INTERLEAVE4(r, g, b, w, a, b2, c, d) \
  (float16)(r.a, g.a, b.a, w.a, r.b2, g.b2, b.b2, w.b2, r.c, g.c, b.c, w.c, r.d, g.d, b.d, w.d)

INLINE void store_texels(__global float4* p, int count, float16 r, float16 g, float16 b,
                         float16 w) {
  const float16 q0 = INTERLEAVE4(r, g, b, w, s0, s1, s2, s3);
  const float16 q1 = INTERLEAVE4(r, g, b, w, s4, s5, s6, s7);
  const float16 q2 = INTERLEAVE4(r, g, b, w, s8, s9, sa, sb);
  const float16 q3 = INTERLEAVE4(r, g, b, w, sc, sd, se, sf);
  if (count == LANES) {
    vstore16(q0, 0, (__global float*)p);
    vstore16(q1, 1, (__global float*)p);
    vstore16(q2, 2, (__global float*)p);
    vstore16(q3, 3, (__global float*)p);
    return;
  }
  float v[4 * LANES];
  vstore16(q0, 0, v);
  vstore16(q1, 1, v);
  vstore16(q2, 2, v);
  vstore16(q3, 3, v);
  for (int j = 0; j < count; ++j) p[j] = vload4(j, v);
}

// The update rules on 16 texels with samples (zr, zg, zb, zq); ok: the lanes with a usable
// sample.
INLINE void merge_lanes(__global float4* texels, __global float4* pending, int i, int count,
                        int16 ok, float16 zr, float16 zg, float16 zb, float16 zq, int rule,
                        int publish, float measurement_var, float process_var,
                        float change_sigma2) {
  if (rule == RULE_KALMAN && !any(ok)) return;
  float16 tr, tg, tb, tw;
  load_texels(texels + i, count, &tr, &tg, &tb, &tw);
  if (rule == RULE_KALMAN) {
    const float16 s = measurement_var / zq;
    const float16 cvar = tw + process_var;  // predict
    const float16 lx = fmax(luminance_lanes(tr, tg, tb), 1e-30f);
    const float16 e = (luminance_lanes(zr, zg, zb) - lx) / lx;
    // A first observation replaces; so does a change beyond change_sigma (a lamp switched).
    const int16 changed = change_sigma2 > 0.0f ? e * e > change_sigma2 * (cvar + s) : (int16)(0);
    const int16 restart = !(tw > 0.0f) | changed;
    const float16 g = cvar / (cvar + s);
    const float16 nr = select(tr + g * (zr - tr), zr, restart);
    const float16 ng = select(tg + g * (zg - tg), zg, restart);
    const float16 nb = select(tb + g * (zb - tb), zb, restart);
    const float16 nw = select((1.0f - g) * cvar, s, restart);
    store_texels(texels + i, count, select(tr, nr, ok), select(tg, ng, ok), select(tb, nb, ok),
                 select(tw, nw, ok));
  } else {
    float16 pr, pg, pb, pw;
    load_texels(pending + i, count, &pr, &pg, &pb, &pw);
    const int16 better = ok & (zq > pw);
    pr = select(pr, zr, better);
    pg = select(pg, zg, better);
    pb = select(pb, zb, better);
    pw = select(pw, zq, better);
    if (publish) {
      const int16 has = pw > 0.0f;
      store_texels(texels + i, count, select(tr, pr, has), select(tg, pg, has), select(tb, pb, has),
                   select(tw, pw, has));
      const float16 zero = (float16)(0.0f);
      store_texels(pending + i, count, zero, zero, zero, zero);
    } else {
      store_texels(pending + i, count, pr, pg, pb, pw);
    }
  }
}

// Bilinear blend of the four corners a (x0, y0), b (x0 + 1, y0), c (x0, y0 + 1), d, per
// channel; ok drops lanes with an unusable corner: a saturated, black or out-of-circle pixel
// must not leak into a texel.
#define BLEND(ch)                  \
  (ch##a + ax * (ch##b - ch##a)) + \
      ay*((ch##c + ax * (ch##d - ch##c)) - (ch##a + ax * (ch##b - ch##a)))

// One pixel per lane from a float4 image, lane j at index idx.sj.
#define GATHER4(image, idx, R, G, B, Q, j)                  \
  {                                                         \
    const float4 p = image[idx.s##j];                       \
    R.s##j = p.x, G.s##j = p.y, B.s##j = p.z, Q.s##j = p.w; \
  }
#define GATHER4_ALL(image, idx, R, G, B, Q) \
  GATHER4(image, idx, R, G, B, Q, 0)        \
  GATHER4(image, idx, R, G, B, Q, 1)        \
  GATHER4(image, idx, R, G, B, Q, 2)        \
  GATHER4(image, idx, R, G, B, Q, 3)        \
  GATHER4(image, idx, R, G, B, Q, 4)        \
  GATHER4(image, idx, R, G, B, Q, 5)        \
  GATHER4(image, idx, R, G, B, Q, 6)        \
  GATHER4(image, idx, R, G, B, Q, 7)        \
  GATHER4(image, idx, R, G, B, Q, 8)        \
  GATHER4(image, idx, R, G, B, Q, 9)        \
  GATHER4(image, idx, R, G, B, Q, a)        \
  GATHER4(image, idx, R, G, B, Q, b)        \
  GATHER4(image, idx, R, G, B, Q, c)        \
  GATHER4(image, idx, R, G, B, Q, d)        \
  GATHER4(image, idx, R, G, B, Q, e)        \
  GATHER4(image, idx, R, G, B, Q, f)

__kernel void envmap_update(__global float4* texels, __global float4* pending,
                            __global const float4* image, int width, int height, int n, float4 r0,
                            float4 r1, float4 r2, __global const float2* lut, int lut_size,
                            float lut_centre, float lut_scale, float lut_max_theta, int parallax,
                            float4 box_lo, float4 box_hi, float4 offset, int rule, int publish,
                            float measurement_var, float process_var, float change_sigma2,
                            float cull_cos) {
  const int x0 = LANES * get_global_id(0), row = get_global_id(1);
  if (x0 >= n || row >= 6 * n) return;
  // Kalman leaves unseen texels as they are; best-score must still publish them.
  if (rule == RULE_KALMAN && group_hidden(n, row, x0, r2, cull_cos)) return;
  int16 px, py;
  float16 ax, ay;
  int16 ok = footprints(n, row, x0, r0, r1, r2, lut, lut_size, lut_centre, lut_scale, lut_max_theta,
                        parallax, box_lo, box_hi, offset, width, height, &px, &py, &ax, &ay);
  if (!any(ok)) {  // none of the 16 texels is seen (the floor, below the horizon): no loads
    const float16 zero = (float16)(0.0f);
    merge_lanes(texels, pending, row * n + x0, min(LANES, n - x0), ok, zero, zero, zero, zero, rule,
                publish, measurement_var, process_var, change_sigma2);
    return;
  }
  const int16 ia = py * width + px, ib = ia + 1, ic = ia + width, id = ic + 1;
  float16 ra, ga, ba, qa, rb, gb, bb, qb, rc, gc, bc, qc, rd, gd, bd, qd;
  GATHER4_ALL(image, ia, ra, ga, ba, qa)
  GATHER4_ALL(image, ib, rb, gb, bb, qb)
  GATHER4_ALL(image, ic, rc, gc, bc, qc)
  GATHER4_ALL(image, id, rd, gd, bd, qd)
  ok &= (qa > 0.0f) & (qb > 0.0f) & (qc > 0.0f) & (qd > 0.0f);
  merge_lanes(texels, pending, row * n + x0, min(LANES, n - x0), ok, BLEND(r), BLEND(g), BLEND(b),
              BLEND(q), rule, publish, measurement_var, process_var, change_sigma2);
}

// Lane j of the raw footprint: the two pixels of the top row and the two of the bottom row
// (3 channels each, minus the black level).
#define RAW_LANE(j)                                                     \
  {                                                                     \
    const __global ushort* top = raw + 3 * (py.s##j * width + px.s##j); \
    const __global ushort* bot = top + 3 * width;                       \
    ra.s##j = top[0], ga.s##j = top[1], ba.s##j = top[2];               \
    rb.s##j = top[3], gb.s##j = top[4], bb.s##j = top[5];               \
    rc.s##j = bot[0], gc.s##j = bot[1], bc.s##j = bot[2];               \
    rd.s##j = bot[3], gd.s##j = bot[4], bd.s##j = bot[5];               \
  }

// From the raw frame (RGB16, linear, not shifted): the four pixels of each footprint
// converted as hdr_conversion does (the constants of hdr_conversion_constants).
__kernel void envmap_update_raw(__global float4* texels, __global float4* pending,
                                __global const ushort* raw, int width, int height, int black_level,
                                int saturated_signal, int black_margin, float radiance_scale,
                                float inv_range, int crop, float circle_cx, float circle_cy,
                                float circle_radius2, int n, float4 r0, float4 r1, float4 r2,
                                __global const float2* lut, int lut_size, float lut_centre,
                                float lut_scale, float lut_max_theta, int parallax, float4 box_lo,
                                float4 box_hi, float4 offset, int rule, int publish,
                                float measurement_var, float process_var, float change_sigma2,
                                float cull_cos) {
  const int x0 = LANES * get_global_id(0), row = get_global_id(1);
  if (x0 >= n || row >= 6 * n) return;
  // Kalman leaves unseen texels as they are; best-score must still publish them.
  if (rule == RULE_KALMAN && group_hidden(n, row, x0, r2, cull_cos)) return;
  int16 px, py;
  float16 ax, ay;
  int16 ok = footprints(n, row, x0, r0, r1, r2, lut, lut_size, lut_centre, lut_scale, lut_max_theta,
                        parallax, box_lo, box_hi, offset, width, height, &px, &py, &ax, &ay);
  if (!any(ok)) {  // none of the 16 texels is seen (the floor, below the horizon): no loads
    const float16 zero = (float16)(0.0f);
    merge_lanes(texels, pending, row * n + x0, min(LANES, n - x0), ok, zero, zero, zero, zero, rule,
                publish, measurement_var, process_var, change_sigma2);
    return;
  }
  int16 ra, ga, ba, rb, gb, bb, rc, gc, bc, rd, gd, bd;
  RAW_LANE(0)
  RAW_LANE(1)
  RAW_LANE(2)
  RAW_LANE(3)
  RAW_LANE(4)
  RAW_LANE(5)
  RAW_LANE(6)
  RAW_LANE(7)
  RAW_LANE(8)
  RAW_LANE(9)
  RAW_LANE(a)
  RAW_LANE(b)
  RAW_LANE(c)
  RAW_LANE(d)
  RAW_LANE(e)
  RAW_LANE(f)
  float16 Ra, Ga, Ba, qa, Rb, Gb, Bb, qb, Rc, Gc, Bc, qc, Rd, Gd, Bd, qd;
  const int16 px1 = px + 1, py1 = py + 1;
#define CONVERT(c, X, Y)                                                                    \
  convert_lanes(r##c - black_level, g##c - black_level, b##c - black_level, X, Y,           \
                saturated_signal, black_margin, radiance_scale, inv_range, crop, circle_cx, \
                circle_cy, circle_radius2, &R##c, &G##c, &B##c, &q##c)
  CONVERT(a, px, py);
  CONVERT(b, px1, py);
  CONVERT(c, px, py1);
  CONVERT(d, px1, py1);
#undef CONVERT
  ok &= (qa > 0.0f) & (qb > 0.0f) & (qc > 0.0f) & (qd > 0.0f);
  merge_lanes(texels, pending, row * n + x0, min(LANES, n - x0), ok, BLEND(R), BLEND(G), BLEND(B),
              BLEND(q), rule, publish, measurement_var, process_var, change_sigma2);
}
