// Guided filter with a colour guide (He, Sun & Tang 2010/2013), the device side of
// guided_filter_reference.cpp. Each work-group owns a TILE_W x TILE_H tile: it loads the tile
// and a RADIUS halo into local memory, then takes box sums by running sums, first along each
// halo row (one work-item per row), then down each column (one work-item per column). The
// work per pixel is a constant add and subtract per moment, whatever the radius.
//
// Build options: -DRADIUS=r -DTILE_W=w -DTILE_H=h, and for gf_mean_apply -DOUTPUT_MODE=m:
//   0 store the window means of (a, b)           (the subsampled filter upsamples them later)
//   1 alpha = virtual > 0 ? clamp(1 - q, 0, 1) : 0 (q is a cost: CVF's feather filter)
//   2 alpha = virtual > 0 ? clamp(q, 0, 1) : 0     (q is a visibility: the Guided baseline)
//   3 alpha = q                                    (the plain filter, for tests)

#define HALO_W (TILE_W + 2 * RADIUS)
#define HALO_H (TILE_H + 2 * RADIUS)
#define TAPS (2 * RADIUS + 1)

// Pixels of the clipped window along one axis.
inline int window_count(int x, int n) {
  return min(n - 1, x + RADIUS) - max(0, x - RADIUS) + 1;
}

// The 13 moments of a guide pixel (r, g, b) and input p: I, p, I p, upper triangle of I I^T.
#define MOMENTS(v, m) \
  m[0] = v.x;         \
  m[1] = v.y;         \
  m[2] = v.z;         \
  m[3] = v.w;         \
  m[4] = v.x * v.w;   \
  m[5] = v.y * v.w;   \
  m[6] = v.z * v.w;   \
  m[7] = v.x * v.x;   \
  m[8] = v.x * v.y;   \
  m[9] = v.x * v.z;   \
  m[10] = v.y * v.y;  \
  m[11] = v.y * v.z;  \
  m[12] = v.z * v.z;

// Loads the tile of `src` (rgb + p, or a + b) with its halo; zero outside the image.
inline void load_tile(__global const float4* src, __local float4* tile, int w, int h) {
  const int x0 = (int)get_group_id(0) * TILE_W - RADIUS;
  const int y0 = (int)get_group_id(1) * TILE_H - RADIUS;
  for (int k = get_local_id(0); k < HALO_W * HALO_H; k += TILE_W) {
    const int gx = x0 + k % HALO_W, gy = y0 + k / HALO_W;
    tile[k] = (gx >= 0 && gx < w && gy >= 0 && gy < h) ? src[gy * w + gx] : (float4)(0.0f);
  }
}

// a = (Sigma + eps U)^-1 cov(I, p), b = mean_p - a . mean_I, from the window means.
inline float4 solve_coefficients(const float* s, float eps) {
  const float mr = s[0], mg = s[1], mb = s[2], mp = s[3];
  const float c0 = s[4] - mr * mp, c1 = s[5] - mg * mp, c2 = s[6] - mb * mp;
  const float m00 = s[7] - mr * mr + eps, m01 = s[8] - mr * mg, m02 = s[9] - mr * mb;
  const float m11 = s[10] - mg * mg + eps, m12 = s[11] - mg * mb, m22 = s[12] - mb * mb + eps;
  const float i00 = m11 * m22 - m12 * m12, i01 = m02 * m12 - m01 * m22;
  const float i02 = m01 * m12 - m02 * m11, i11 = m00 * m22 - m02 * m02;
  const float i12 = m01 * m02 - m00 * m12, i22 = m00 * m11 - m01 * m01;
  const float inv = 1.0f / (m00 * i00 + m01 * i01 + m02 * i02);
  const float a0 = (i00 * c0 + i01 * c1 + i02 * c2) * inv;
  const float a1 = (i01 * c0 + i11 * c1 + i12 * c2) * inv;
  const float a2 = (i02 * c0 + i12 * c1 + i22 * c2) * inv;
  return (float4)(a0, a1, a2, mp - a0 * mr - a1 * mg - a2 * mb);
}

// guide_p: rgb in [0,1] and the input p in .w. Writes (a_r, a_g, a_b, b) per pixel.
__kernel __attribute__((reqd_work_group_size(TILE_W, 1, 1))) void gf_coefficients(
    __global const float4* guide_p, __global float4* ab, int w, int h, float eps) {
  __local float4 tile[HALO_W * HALO_H];
  __local float hsum[13 * HALO_H * TILE_W];
  load_tile(guide_p, tile, w, h);
  barrier(CLK_LOCAL_MEM_FENCE);
  const int li = get_local_id(0);
  for (int row = li; row < HALO_H; row += TILE_W) {
    __local const float4* t = tile + row * HALO_W;
    float s[13], m[13];
    for (int c = 0; c < 13; ++c) s[c] = 0.0f;
    for (int k = 0; k < TAPS; ++k) {
      const float4 v = t[k];
      MOMENTS(v, m);
      for (int c = 0; c < 13; ++c) s[c] += m[c];
    }
    for (int x = 0;; ++x) {
      for (int c = 0; c < 13; ++c) hsum[(c * HALO_H + row) * TILE_W + x] = s[c];
      if (x + 1 == TILE_W) break;
      const float4 vin = t[x + TAPS], vout = t[x];
      float mo[13];
      MOMENTS(vin, m);
      MOMENTS(vout, mo);
      for (int c = 0; c < 13; ++c) s[c] += m[c] - mo[c];
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const int gx = (int)get_group_id(0) * TILE_W + li;
  if (gx >= w) return;
  const int gy0 = (int)get_group_id(1) * TILE_H;
  const float nx = (float)window_count(gx, w);
  float s[13], mean[13];
  for (int c = 0; c < 13; ++c) {
    s[c] = 0.0f;
    for (int k = 0; k < TAPS; ++k) s[c] += hsum[(c * HALO_H + k) * TILE_W + li];
  }
  for (int r = 0; r < TILE_H && gy0 + r < h; ++r) {
    if (r > 0)
      for (int c = 0; c < 13; ++c)
        s[c] += hsum[(c * HALO_H + r + TAPS - 1) * TILE_W + li] -
                hsum[(c * HALO_H + r - 1) * TILE_W + li];
    const float inv_n = 1.0f / (nx * (float)window_count(gy0 + r, h));
    for (int c = 0; c < 13; ++c) mean[c] = s[c] * inv_n;
    ab[(gy0 + r) * w + gx] = solve_coefficients(mean, eps);
  }
}

// Window means of (a, b); then, by OUTPUT_MODE, stores them or applies them to the guide.
__kernel __attribute__((reqd_work_group_size(TILE_W, 1, 1))) void gf_mean_apply(
    __global const float4* ab, int w, int h, __global float4* mean_ab,
    __global const float4* guide_p, __global const float* virtual_mm, __global float* alpha) {
  __local float4 tile[HALO_W * HALO_H];
  __local float4 hsum[HALO_H * TILE_W];
  load_tile(ab, tile, w, h);
  barrier(CLK_LOCAL_MEM_FENCE);
  const int li = get_local_id(0);
  for (int row = li; row < HALO_H; row += TILE_W) {
    __local const float4* t = tile + row * HALO_W;
    float4 s = (float4)(0.0f);
    for (int k = 0; k < TAPS; ++k) s += t[k];
    for (int x = 0;; ++x) {
      hsum[row * TILE_W + x] = s;
      if (x + 1 == TILE_W) break;
      s += t[x + TAPS] - t[x];
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const int gx = (int)get_group_id(0) * TILE_W + li;
  if (gx >= w) return;
  const int gy0 = (int)get_group_id(1) * TILE_H;
  const float nx = (float)window_count(gx, w);
  float4 s = (float4)(0.0f);
  for (int k = 0; k < TAPS; ++k) s += hsum[k * TILE_W + li];
  for (int r = 0; r < TILE_H && gy0 + r < h; ++r) {
    if (r > 0) s += hsum[(r + TAPS - 1) * TILE_W + li] - hsum[(r - 1) * TILE_W + li];
    const float4 m = s / (nx * (float)window_count(gy0 + r, h));
    const int i = (gy0 + r) * w + gx;
#if OUTPUT_MODE == 0
    mean_ab[i] = m;
#else
    const float4 g = guide_p[i];
    const float q = m.x * g.x + m.y * g.y + m.z * g.z + m.w;
#if OUTPUT_MODE == 1
    alpha[i] = virtual_mm[i] > 0.0f ? clamp(1.0f - q, 0.0f, 1.0f) : 0.0f;
#elif OUTPUT_MODE == 3
    alpha[i] = q;
#else
    alpha[i] = virtual_mm[i] > 0.0f ? clamp(q, 0.0f, 1.0f) : 0.0f;
#endif
#endif
  }
}
