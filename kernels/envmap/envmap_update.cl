// Environment-map keyframe update (thesis ch. 6; docs/light-capture.md). Each work-item
// updates 8 neighbouring texels of one row of the n x 6n texel image (face = row / n): their
// world directions (with a room box: the direction from the fisheye's centre to where the
// texel's ray from the keyframe's position leaves the box), rotated into the fisheye's frame,
// projected through the Kannala-Brandt model, bilinearly sampled, then merged by the selected
// rule. envmap_update_reference.cpp mirrors every step in float, lane by lane.
//
// Why 8 texels per work-item in explicit float8 code, with selects and unconditional loads:
// PoCL 3.1 ran the one-texel-per-work-item version as scalar code (no vectorisation across
// work-items), and most of its time was spent waiting for the scattered pixel loads one
// texel at a time; here the 32 pixel loads of 8 texels are independent, so the CPU overlaps
// their cache misses, and the arithmetic runs 8 wide (docs/performance.md "Light capture:
// bench light").
//
// Two entry points differ only in what they sample: envmap_update_raw converts the four raw
// pixels of each footprint with the HDR conversion's own formulas (the program is
// hdr_conversion.cl followed by this file, whose FP_CONTRACT OFF then covers both; convert8
// below is its convert_one lane by lane), so a frame is never converted whole (98k texels
// read ~400k of a 1024 px frame's 1M pixels, and nothing is written back); envmap_update
// samples an already converted image (rgb radiance, a quality, 0 = unusable).
#define RULE_KALMAN 0
#define RULE_BEST_SCORE 1
#define LANES 8
#define INLINE inline __attribute__((always_inline))

// OpenGL cube map face coordinates -> directions (not normalised; core/cubemap.cpp), for 8
// lanes of one row: sc = 2u - 1 per lane, tc = 2v - 1 shared.
INLINE void cube_directions(int face, float8 sc, float tc, float8* dx, float8* dy, float8* dz) {
  const float8 t = (float8)(tc), one = (float8)(1.0f);
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
INLINE float8 polar_angle(float8 r, float8 z) {
  const float8 az = fabs(z);
  const float8 hi = fmax(r, az), lo = fmin(r, az);
  const float8 x = select((float8)(0.0f), lo / hi, hi > 0.0f), x2 = x * x;
  float8 a =
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

// The geometry of the 8 texels x0 .. x0 + 7 of `row`: the top-left pixel of each bilinear
// footprint (pixel centres on integers) and its weights. Returns the lanes the fisheye sees
// (within max_theta, footprint inside the image, x < n); other lanes get footprint (0, 0),
// so that every load stays inside the image.
INLINE int8 footprints(int n, int row, int x0, float4 r0, float4 r1, float4 r2, float4 f, float4 k,
                       float max_theta, int parallax, float4 box_lo, float4 box_hi, float4 offset,
                       int width, int height, int8* px, int8* py, float8* ax, float8* ay) {
  const int face = row / n, y = row - face * n;
  const float inv_n = 1.0f / (float)n;
  const float8 xs = (float8)((float)x0) + (float8)(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f);
  const float8 sc = 2.0f * ((xs + 0.5f) * inv_n) - 1.0f;
  const float tc = 2.0f * (((float)y + 0.5f) * inv_n) - 1.0f;
  float8 dx, dy, dz;
  cube_directions(face, sc, tc, &dx, &dy, &dz);
  float8 wx = dx, wy = dy, wz = dz;
  if (parallax) {
    // Exit of the ray k + t d from the box (box_lo, box_hi relative to k; k inside, so every
    // axis gives t >= 0 or +inf (NaN for 0 / 0, which fmax drops), the major axis a finite
    // one); then the wall point seen from the fisheye: (k - c) + t d. envmap_types.cpp's
    // box_exit / parallax_direction.
    const float8 tx = fmax(box_lo.x / dx, box_hi.x / dx);
    const float8 ty = fmax(box_lo.y / dy, box_hi.y / dy);
    const float8 tz = fmax(box_lo.z / dz, box_hi.z / dz);
    const float8 t = fmin(tx, fmin(ty, tz));
    wx = offset.x + t * dx;
    wy = offset.y + t * dy;
    wz = offset.z + t * dz;
  }
  const float8 cx = r0.x * wx + r0.y * wy + r0.z * wz;
  const float8 cy = r1.x * wx + r1.y * wy + r1.z * wz;
  const float8 cz = r2.x * wx + r2.y * wy + r2.z * wz;
  // Kannala-Brandt (core/camera/kannala_brandt.cpp); on the axis (r = 0) the centre.
  const float8 r = sqrt(cx * cx + cy * cy);
  const float8 theta = polar_angle(r, cz);
  const float8 t2 = theta * theta;
  const float8 theta_d = theta * (1.0f + t2 * (k.x + t2 * (k.y + t2 * (k.z + t2 * k.w))));
  const float8 s = theta_d / r;
  const int8 on_axis = r == 0.0f;
  const float8 u = select(f.x * s * cx + f.z, (float8)(f.z), on_axis);
  const float8 v = select(f.y * s * cy + f.w, (float8)(f.w), on_axis);
  const float8 fx0 = floor(u), fy0 = floor(v);
  const int8 lane = (int8)(0, 1, 2, 3, 4, 5, 6, 7);
  const int8 seen = (theta <= max_theta) & (~on_axis | (cz > 0.0f)) & (fx0 >= 0.0f) &
                    (fy0 >= 0.0f) & (fx0 + 1.0f < (float)width) & (fy0 + 1.0f < (float)height) &
                    (lane < n - x0);
  // Unseen lanes may hold NaN or huge values: zero them before the conversion to int.
  *px = convert_int8(select((float8)(0.0f), fx0, seen));
  *py = convert_int8(select((float8)(0.0f), fy0, seen));
  *ax = u - fx0;
  *ay = v - fy0;
  return seen;
}

// The HDR conversion of 8 pixels (hdr_conversion.cl's convert_one, lane by lane): r, g, b
// are raw - black. Writes radiance and quality (0 = unusable).
INLINE void convert8(int8 r, int8 g, int8 b, int8 x, int8 y, int saturated_signal, int black_margin,
                     float radiance_scale, float inv_range, int crop, float circle_cx,
                     float circle_cy, float circle_radius2, float8* R, float8* G, float8* B,
                     float8* Q) {
  const int8 peak = max(r, max(g, b));
  const float8 dx = convert_float8(x) - circle_cx;
  const float8 dy = convert_float8(y) - circle_cy;
  const float8 d2 = dx * dx + dy * dy;
  const int8 inside = crop ? (d2 <= circle_radius2) : (int8)(-1);
  const int8 usable = (peak < saturated_signal) & (peak > black_margin) & inside;
  const float8 level = convert_float8(peak) * inv_range;
  const float8 hat = max(2.0f * min(level, 1.0f - level), MIN_USABLE_QUALITY);
  *Q = select((float8)(0.0f), hat, usable);
  *R = convert_float8(max(r, 0)) * radiance_scale;
  *G = convert_float8(max(g, 0)) * radiance_scale;
  *B = convert_float8(max(b, 0)) * radiance_scale;
}

INLINE float8 luminance8(float8 r, float8 g, float8 b) {
  return 0.2126f * r + 0.7152f * g + 0.0722f * b;
}

// Texels x0 .. x0 + count - 1 (count <= 8) of a float4 image as four float8 channels.
INLINE void load_texels(__global const float4* p, int count, float8* r, float8* g, float8* b,
                        float8* w) {
  if (count == LANES) {
    const float16 lo = vload16(0, (__global const float*)p);
    const float16 hi = vload16(1, (__global const float*)p);
    *r = (float8)(lo.s048c, hi.s048c);
    *g = (float8)(lo.s159d, hi.s159d);
    *b = (float8)(lo.s26ae, hi.s26ae);
    *w = (float8)(lo.s37bf, hi.s37bf);
    return;
  }
  float v[4 * LANES];
  for (int i = 0; i < 4 * LANES; ++i) v[i] = 0.0f;
  for (int j = 0; j < count; ++j) vstore4(p[j], j, v);
  *r = (float8)(v[0], v[4], v[8], v[12], v[16], v[20], v[24], v[28]);
  *g = (float8)(v[1], v[5], v[9], v[13], v[17], v[21], v[25], v[29]);
  *b = (float8)(v[2], v[6], v[10], v[14], v[18], v[22], v[26], v[30]);
  *w = (float8)(v[3], v[7], v[11], v[15], v[19], v[23], v[27], v[31]);
}

INLINE void store_texels(__global float4* p, int count, float8 r, float8 g, float8 b, float8 w) {
  const float16 lo = (float16)(r.s0, g.s0, b.s0, w.s0, r.s1, g.s1, b.s1, w.s1, r.s2, g.s2, b.s2,
                               w.s2, r.s3, g.s3, b.s3, w.s3);
  const float16 hi = (float16)(r.s4, g.s4, b.s4, w.s4, r.s5, g.s5, b.s5, w.s5, r.s6, g.s6, b.s6,
                               w.s6, r.s7, g.s7, b.s7, w.s7);
  if (count == LANES) {
    vstore16(lo, 0, (__global float*)p);
    vstore16(hi, 1, (__global float*)p);
    return;
  }
  float v[4 * LANES];
  vstore16(lo, 0, v);
  vstore16(hi, 1, v);
  for (int j = 0; j < count; ++j) p[j] = vload4(j, v);
}

// The update rules on 8 texels with samples (zr, zg, zb, zq); ok: the lanes with a usable
// sample.
INLINE void merge8(__global float4* texels, __global float4* pending, int i, int count, int8 ok,
                   float8 zr, float8 zg, float8 zb, float8 zq, int rule, int publish,
                   float measurement_var, float process_var, float change_sigma2) {
  float8 tr, tg, tb, tw;
  load_texels(texels + i, count, &tr, &tg, &tb, &tw);
  if (rule == RULE_KALMAN) {
    if (!any(ok)) return;
    const float8 s = measurement_var / zq;
    const float8 cvar = tw + process_var;  // predict
    const float8 lx = fmax(luminance8(tr, tg, tb), 1e-30f);
    const float8 e = (luminance8(zr, zg, zb) - lx) / lx;
    // A first observation replaces; so does a change beyond change_sigma (a lamp switched).
    const int8 changed = change_sigma2 > 0.0f ? e * e > change_sigma2 * (cvar + s) : (int8)(0);
    const int8 restart = !(tw > 0.0f) | changed;
    const float8 g = cvar / (cvar + s);
    const float8 nr = select(tr + g * (zr - tr), zr, restart);
    const float8 ng = select(tg + g * (zg - tg), zg, restart);
    const float8 nb = select(tb + g * (zb - tb), zb, restart);
    const float8 nw = select((1.0f - g) * cvar, s, restart);
    store_texels(texels + i, count, select(tr, nr, ok), select(tg, ng, ok), select(tb, nb, ok),
                 select(tw, nw, ok));
  } else {
    float8 pr, pg, pb, pw;
    load_texels(pending + i, count, &pr, &pg, &pb, &pw);
    const int8 better = ok & (zq > pw);
    pr = select(pr, zr, better);
    pg = select(pg, zg, better);
    pb = select(pb, zb, better);
    pw = select(pw, zq, better);
    if (publish) {
      const int8 has = pw > 0.0f;
      store_texels(texels + i, count, select(tr, pr, has), select(tg, pg, has), select(tb, pb, has),
                   select(tw, pw, has));
      const float8 zero = (float8)(0.0f);
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
  GATHER4(image, idx, R, G, B, Q, 7)

__kernel void envmap_update(__global float4* texels, __global float4* pending,
                            __global const float4* image, int width, int height, int n, float4 r0,
                            float4 r1, float4 r2, float4 focal_centre, float4 k, float max_theta,
                            int parallax, float4 box_lo, float4 box_hi, float4 offset, int rule,
                            int publish, float measurement_var, float process_var,
                            float change_sigma2) {
  const int x0 = LANES * get_global_id(0), row = get_global_id(1);
  if (x0 >= n || row >= 6 * n) return;
  int8 px, py;
  float8 ax, ay;
  int8 ok = footprints(n, row, x0, r0, r1, r2, focal_centre, k, max_theta, parallax, box_lo, box_hi,
                       offset, width, height, &px, &py, &ax, &ay);
  const int8 ia = py * width + px, ib = ia + 1, ic = ia + width, id = ic + 1;
  float8 ra, ga, ba, qa, rb, gb, bb, qb, rc, gc, bc, qc, rd, gd, bd, qd;
  GATHER4_ALL(image, ia, ra, ga, ba, qa)
  GATHER4_ALL(image, ib, rb, gb, bb, qb)
  GATHER4_ALL(image, ic, rc, gc, bc, qc)
  GATHER4_ALL(image, id, rd, gd, bd, qd)
  ok &= (qa > 0.0f) & (qb > 0.0f) & (qc > 0.0f) & (qd > 0.0f);
  merge8(texels, pending, row * n + x0, min(LANES, n - x0), ok, BLEND(r), BLEND(g), BLEND(b),
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
                                float4 focal_centre, float4 k, float max_theta, int parallax,
                                float4 box_lo, float4 box_hi, float4 offset, int rule, int publish,
                                float measurement_var, float process_var, float change_sigma2) {
  const int x0 = LANES * get_global_id(0), row = get_global_id(1);
  if (x0 >= n || row >= 6 * n) return;
  int8 px, py;
  float8 ax, ay;
  int8 ok = footprints(n, row, x0, r0, r1, r2, focal_centre, k, max_theta, parallax, box_lo, box_hi,
                       offset, width, height, &px, &py, &ax, &ay);
  int8 ra, ga, ba, rb, gb, bb, rc, gc, bc, rd, gd, bd;
  RAW_LANE(0)
  RAW_LANE(1)
  RAW_LANE(2)
  RAW_LANE(3)
  RAW_LANE(4)
  RAW_LANE(5)
  RAW_LANE(6)
  RAW_LANE(7)
  float8 Ra, Ga, Ba, qa, Rb, Gb, Bb, qb, Rc, Gc, Bc, qc, Rd, Gd, Bd, qd;
  const int8 px1 = px + 1, py1 = py + 1;
#define CONVERT(c, X, Y)                                                                        \
  convert8(r##c - black_level, g##c - black_level, b##c - black_level, X, Y, saturated_signal,  \
           black_margin, radiance_scale, inv_range, crop, circle_cx, circle_cy, circle_radius2, \
           &R##c, &G##c, &B##c, &q##c)
  CONVERT(a, px, py);
  CONVERT(b, px1, py);
  CONVERT(c, px, py1);
  CONVERT(d, px1, py1);
#undef CONVERT
  ok &= (qa > 0.0f) & (qb > 0.0f) & (qc > 0.0f) & (qd > 0.0f);
  merge8(texels, pending, row * n + x0, min(LANES, n - x0), ok, BLEND(R), BLEND(G), BLEND(B),
         BLEND(q), rule, publish, measurement_var, process_var, change_sigma2);
}
