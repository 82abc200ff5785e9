// The guided filter with a colour guide (He, Sun & Tang 2010/2013) as ONE row-streaming
// kernel: coefficients, their window means and the output in a single pass, with CVF's cost
// or threshold computed on the fly as its input. The device side of
// guided_filter_reference.cpp; docs/occlusion.md "Speed" has the measurements behind it.
//
// Layout: one work-item per strip of rows, covering the whole width in explicit float16
// vectors of 16 columns (PoCL did not vectorise the implicit loop over work-items of the
// earlier tile kernels; explicit vectors are SIMD whatever the work-group compiler does).
// Per row t the work-item
//   1. computes the input (r, g, b, p) of row t + RADIUS, keeps it in a ring of rows and
//      updates the running column sums of the 13 moments (the row entering the window is
//      added, the row leaving it subtracted);
//   2. turns the column sums into window sums by a running sum along the row (per vector:
//      the differences col(x + r) - col(x - r - 1), a prefix sum inside the vector, and the
//      carry from the previous vector) and solves for (a, b) of row t, kept in a second ring
//      with their own running column sums;
//   3. takes the window sums of (a, b) the same way and writes row t - RADIUS of the output.
// Every box sum is one add and one subtract per pixel in each direction plus a 4-step
// in-vector prefix: the cost per pixel does not depend on the radius (up to 16).
//
// Scratch (global, per strip): the two rings and the two rows of column sums, each row
// SROW = PAD + round_up(w, 16) + PAD floats with zero padding on both sides.
//
// Build options: -DRADIUS=r, -DINPUT_MODE=i, -DOUTPUT_MODE=o, -DTRACE=0/1, and for the CVF
// inputs -DBINS=b -DSUBSAMPLE=s -DLOCAL=0/1 (with LOCAL=1 -DTILE=t -DPRIOR=r -DSOFT=0/1).
//   LOCAL 0: the thesis's CVF, one pair of colour models per frame (cvf_reference.cpp).
//   LOCAL 1: the shipped CVF with local colour models (cvf_local_reference.cpp): a process
//     pixel's cost is the posterior from the 4 nearest tiles' likelihoods and the window prior
//     counted by cvf.cl; the threshold keeps the filtered cost with weight s (the softness).
//   INPUT_MODE 0: packed (r, g, b, p) float4 per pixel           (the plain filter, tests)
//   INPUT_MODE 1: CVF's cost, block-averaged over SUBSAMPLE^2 with the guide (the wide filter)
//   INPUT_MODE 2: CVF's threshold of the wide filter's upsampled output (the feather filter)
//   OUTPUT_MODE 0: the window means of (a, b), 4 planes   (the subsampled filter: upsampled later)
//   OUTPUT_MODE 1: alpha = virtual > 0 ? clamp(1 - q, 0, 1) : 0 (q a cost: CVF's feather)
//   OUTPUT_MODE 3: alpha = q                                      (the plain filter, tests)
// With TRACE=1 the input of every pixel is also stored as 4 planes (tests).

// (cvf_vector.cl is prepended: VW, PAD, vf, vi and the vector helpers.)
#define NRING (2 * RADIUS + 2)
// The wide filter's mean coefficients (OUTPUT_MODE 0, read by INPUT_MODE 2) are stored with
// MEAN_PAD columns on each side that repeat the edge values, so the feather filter's
// bilinear upsampling is one vector path up to the image border (clamping there gives the
// edge value, which interpolating between two copies of it reproduces exactly).
#define MEAN_PAD 16

#define CAT_IGNORE 0
#define CAT_BEHIND 1
#define CAT_INFRONT 2
#define CAT_PROCESS 3
#ifndef LOCAL
#define LOCAL 0
#endif

inline int window_count(int x, int n) {
  return min(n - 1, x + RADIUS) - max(0, x - RADIUS) + 1;
}

inline int ring_slot(int y) {
  return ((y % NRING) + NRING) % NRING;
}

// Window sums of the 16 columns from x on, from the running carry (the window sum of column
// x - 1): S(x) = S(x - 1) + col(x + r) - col(x - r - 1). `col` points at column 0.
inline vf window_sums(__global const float* col, int x, vf* carry) {
  return running_window_sums(col, x, RADIUS, carry);
}

// ---- Inputs: input_row() fills 4 planes (r, g, b, p) for the 16 pixels from (x0, y) ------

#if INPUT_MODE == 0
#define INPUT_ARGS __global const float4* guide_p
#define INPUT_PASS guide_p
#define INPUT_SETUP
inline float4 input_pixel(int x, int y, int w, int h, INPUT_ARGS) {
  return guide_p[y * w + x];
}
inline bool input_fast(int x0, int y, int w, int h, INPUT_ARGS) {
  return false;
}
__attribute__((always_inline)) inline void input_vec(int x0, int y, int w, int h, vf* v,
                                                     INPUT_ARGS) {}

#elif INPUT_MODE == 1
#define NBINS (BINS * BINS * BINS)
#if LOCAL
// lik: per tile the shrunk likelihoods P(bin | infront) [0, NBINS) and P(bin | behind)
// [NBINS, 2 NBINS) (cvf_local_histogram.cl: cvf_local_likelihoods); stats[0] = 1 when the
// frame's pair had min_samples per class; prior: the window counts (infront, behind) (cvf.cl).
#define INPUT_ARGS                                                                             \
  __global const uchar *rgb, __global const uchar *categories, __global const ushort *real_mm, \
      __global const float *virtual_mm, __global const float *lik, __global const int *stats,  \
      __global const uchar *prior, int tiles_x, int tiles_y, int full_w, int full_h
#define INPUT_PASS \
  rgb, categories, real_mm, virtual_mm, lik, stats, prior, tiles_x, tiles_y, full_w, full_h
#define INPUT_SETUP
#define MODELS_VALID (stats[0] != 0)
#else
// hist: infront counts [0, NBINS), behind [NBINS, 2 NBINS), then the two totals. table: the
// process cost of every bin, table[NBINS] = 1 when the colour models are valid.
#define INPUT_ARGS                                                                             \
  __global const uchar *rgb, __global const uchar *categories, __global const ushort *real_mm, \
      __global const float *virtual_mm, __local const float *table, int full_w, int full_h
#define INPUT_PASS rgb, categories, real_mm, virtual_mm, table, full_w, full_h
#define INPUT_SETUP                                                          \
  __local float table[NBINS + 1];                                            \
  {                                                                          \
    const uint tin = hist[2 * NBINS], tbe = hist[2 * NBINS + 1];             \
    const bool valid = tin >= (uint)min_samples && tbe >= (uint)min_samples; \
    for (int k = 0; k < NBINS; ++k) {                                        \
      const float p_in = valid ? (float)hist[k] / (float)tin : 0.0f;         \
      const float p_be = valid ? (float)hist[NBINS + k] / (float)tbe : 0.0f; \
      table[k] = p_in + p_be > 0.0f ? p_in / (p_in + p_be) : 0.5f;           \
    }                                                                        \
    table[NBINS] = valid ? 1.0f : 0.0f;                                      \
  }
#define MODELS_VALID (table[NBINS] != 0.0f)
#endif

inline int colour_bin(uint r, uint g, uint b) {
  return ((r * BINS / 256) * BINS + g * BINS / 256) * BINS + b * BINS / 256;
}

#if LOCAL
// Tile centres at (t + 0.5) TILE; beyond the outermost centres the nearest one holds
// (tile_blend() in cvf_local_reference.cpp).
inline void blend_axis(int p, int tiles, int* t0, int* t1, float* f) {
  const float u = clamp(((float)p + 0.5f) / (float)TILE - 0.5f, 0.0f, (float)(tiles - 1));
  *t0 = min((int)u, tiles - 1);
  *t1 = min(*t0 + 1, tiles - 1);
  *f = u - (float)*t0;
}

// The local posterior of a process pixel (local_cost() in cvf_local_reference.cpp): the 4
// nearest tiles' likelihoods blended bilinearly, times the Laplace-smoothed window prior.
inline float process_cost(int x, int y, int bin, INPUT_ARGS) {
  int x0, x1, y0, y1;
  float fx, fy;
  blend_axis(x, tiles_x, &x0, &x1, &fx);
  blend_axis(y, tiles_y, &y0, &y1, &fy);
  const int tile[4] = {y0 * tiles_x + x0, y0 * tiles_x + x1, y1 * tiles_x + x0, y1 * tiles_x + x1};
  const float wt[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
  float p_in = 0.0f, p_be = 0.0f;
  for (int k = 0; k < 4; ++k) {
    __global const float* l = lik + (size_t)tile[k] * 2 * NBINS;
    p_in += wt[k] * l[bin];
    p_be += wt[k] * l[NBINS + bin];
  }
#if PRIOR > 0
  const size_t i = (size_t)y * full_w + x;
  const float ni = (float)prior[2 * i] + 1.0f, nb = (float)prior[2 * i + 1] + 1.0f;
  p_in *= ni / (ni + nb);
  p_be *= nb / (ni + nb);
#endif
  return p_in + p_be > 0.0f ? p_in / (p_in + p_be) : 0.5f;
}
#else
inline float process_cost(int x, int y, int bin, INPUT_ARGS) {
  return table[bin];
}
#endif

// Cost of one pixel (thesis 3.3.3; cvf_cost() in cvf_reference.cpp), with its colour.
inline float4 cost_pixel(int x, int y, INPUT_ARGS) {
  const int i = y * full_w + x;
  const uint r = rgb[3 * i], g = rgb[3 * i + 1], b = rgb[3 * i + 2];
  const int c = categories[i] & 3;
  float cost;
  if (c == CAT_INFRONT) {
    cost = 1.0f;
  } else if (c == CAT_BEHIND) {
    cost = 0.0f;
  } else if (c == CAT_IGNORE) {
    cost = 0.5f;
  } else if (!MODELS_VALID) {
    const ushort d = real_mm[i];
    cost = d == 0 ? 0.5f : ((float)d < virtual_mm[i] ? 1.0f : 0.0f);
  } else {
    cost = process_cost(x, y, colour_bin(r, g, b), INPUT_PASS);
  }
  return (float4)((float)r * (1.0f / 255.0f), (float)g * (1.0f / 255.0f),
                  (float)b * (1.0f / 255.0f), cost);
}

// (r, g, b, cost) averaged over the in-image part of the SUBSAMPLE^2 block.
inline float4 input_pixel(int xl, int yl, int w, int h, INPUT_ARGS) {
  float4 sum = (float4)(0.0f);
  float n = 0.0f;
  for (int dy = 0; dy < SUBSAMPLE; ++dy)
    for (int dx = 0; dx < SUBSAMPLE; ++dx) {
      const int x = xl * SUBSAMPLE + dx, y = yl * SUBSAMPLE + dy;
      if (x < full_w && y < full_h) {
        sum += cost_pixel(x, y, INPUT_PASS);
        n += 1.0f;
      }
    }
  return sum / n;
}

// Costs of 16 full-resolution pixels from (x0, y).
__attribute__((always_inline)) inline vf cost_vec(int x0, int y, vf r, vf g, vf b, INPUT_ARGS) {
  const int i = y * full_w + x0;
  const vi c = convert_int16(LOADU8(categories + i) & (uchar16)(3));
  vf cost = select((vf)(0.5f), (vf)(1.0f), c == CAT_INFRONT);
  cost = select(cost, (vf)(0.0f), c == CAT_BEHIND);
  const vi process = c == CAT_PROCESS;
  if (any(process)) {
    vf pc;
    if (!MODELS_VALID) {
      const vf d = convert_float16(LOADU16(real_mm + i));
      const vf v = LOADF(virtual_mm + i);
      pc = select(select((vf)(0.0f), (vf)(1.0f), d < v), (vf)(0.5f), d == 0.0f);
    } else {
      const vi bin =
          ((convert_int16(r) * BINS / 256) * BINS + convert_int16(g) * BINS / 256) * BINS +
          convert_int16(b) * BINS / 256;
      int bins[VW], proc[VW];
      float t[VW];
      vstore16(bin, 0, bins);
      vstore16(process, 0, proc);
      for (int k = 0; k < VW; ++k)
        t[k] = proc[k] ? process_cost(x0 + k, y, bins[k], INPUT_PASS) : 0.0f;
      pc = vload16(0, t);
    }
    cost = select(cost, pc, process);
  }
  return cost;
}

inline bool input_fast(int x0, int y, int w, int h, INPUT_ARGS) {
  return SUBSAMPLE == 1 ? x0 + VW <= w
                        : SUBSAMPLE == 2 && 2 * x0 + 2 * VW <= full_w && 2 * y + 1 < full_h;
}

// SUBSAMPLE 1: 16 pixels as they are; 2: the 2x2 block averages of 32 x 2 pixels.
__attribute__((always_inline)) inline void input_vec(int x0, int y, int w, int h, vf* v,
                                                     INPUT_ARGS) {
#if SUBSAMPLE == 1
  const int i = y * full_w + x0;
  vf r, g, b;
  load_rgb16(rgb + 3 * i, &r, &g, &b);
  v[3] = cost_vec(x0, y, r, g, b, INPUT_PASS);
  v[0] = r * (1.0f / 255.0f);
  v[1] = g * (1.0f / 255.0f);
  v[2] = b * (1.0f / 255.0f);
  return;
#endif
  vf s[4] = {(vf)(0.0f), (vf)(0.0f), (vf)(0.0f), (vf)(0.0f)};
  for (int dy = 0; dy < 2; ++dy) {
    vf q[2][4];
    for (int part = 0; part < 2; ++part) {
      const int i = (2 * y + dy) * full_w + 2 * x0 + VW * part;
      vf r, g, b;
      load_rgb16(rgb + 3 * i, &r, &g, &b);
      q[part][3] = cost_vec(2 * x0 + VW * part, 2 * y + dy, r, g, b, INPUT_PASS);
      q[part][0] = r * (1.0f / 255.0f);
      q[part][1] = g * (1.0f / 255.0f);
      q[part][2] = b * (1.0f / 255.0f);
    }
    for (int c = 0; c < 4; ++c)
      s[c] += __builtin_shufflevector(q[0][c], q[1][c], 0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22,
                                      24, 26, 28, 30) +
              __builtin_shufflevector(q[0][c], q[1][c], 1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23,
                                      25, 27, 29, 31);
  }
  for (int c = 0; c < 4; ++c) v[c] = s[c] * 0.25f;
}

#elif INPUT_MODE == 2
// mean_ab: the wide filter's mean coefficients at 1/SUBSAMPLE resolution, 4 planes of wl x hl
// with rows of wl + 2 MEAN_PAD (column x at MEAN_PAD + x).
#if LOCAL
// prior: the window counts (infront, behind) (cvf.cl); overlap[0]: the Bhattacharyya
// coefficient of the frame's two colour models; stats[0] = 1 when they are valid.
#define INPUT_ARGS                                                                            \
  __global const uchar *rgb, __global const uchar *categories, __global const float *mean_ab, \
      int wl, int hl, __global const uchar *prior, __global const float *overlap,             \
      __global const int *stats
#define INPUT_PASS rgb, categories, mean_ab, wl, hl, prior, overlap, stats
#else
#define INPUT_ARGS                                                                            \
  __global const uchar *rgb, __global const uchar *categories, __global const float *mean_ab, \
      int wl, int hl
#define INPUT_PASS rgb, categories, mean_ab, wl, hl
#endif
#define INPUT_SETUP

// The threshold of the wide filter's output q on process pixels: CVF's q > 0.5, and with
// LOCAL its blend with the soft q, weight s = overlap x 4 pi_in pi_behind (step 3 of
// docs/occlusion.md "CVF with local colour models"; cvf_local_reference.cpp).
#if LOCAL && SOFT
inline float softness(int i, INPUT_ARGS) {
  if (!stats[0]) return 0.0f;
#if PRIOR > 0
  const float ni = (float)prior[2 * i] + 1.0f, nb = (float)prior[2 * i + 1] + 1.0f;
  const float ambiguity = 4.0f * ni * nb / ((ni + nb) * (ni + nb));
#else
  const float ambiguity = 1.0f;
#endif
  return clamp(overlap[0] * ambiguity, 0.0f, 1.0f);
}
#endif

// The wide filter's output at (x, y) (mean a, b upsampled bilinearly when SUBSAMPLE > 1),
// thresholded: infront 1, behind 0, else q > 0.5 (thesis 3.3.4), with the guide.
inline float4 input_pixel(int x, int y, int w, int h, INPUT_ARGS) {
  const int i = y * w + x;
  const float3 I =
      (float3)((float)rgb[3 * i], (float)rgb[3 * i + 1], (float)rgb[3 * i + 2]) * (1.0f / 255.0f);
  const int pitch = wl + 2 * MEAN_PAD, plane = pitch * hl;
  float m[4];
#if SUBSAMPLE == 1
  for (int c = 0; c < 4; ++c) m[c] = mean_ab[c * plane + y * pitch + MEAN_PAD + x];
#else
  const float u = clamp(((float)x + 0.5f) / SUBSAMPLE - 0.5f, 0.0f, (float)(wl - 1));
  const float v = clamp(((float)y + 0.5f) / SUBSAMPLE - 0.5f, 0.0f, (float)(hl - 1));
  const int x0 = (int)u, y0 = (int)v;
  const int x1 = min(x0 + 1, wl - 1), y1 = min(y0 + 1, hl - 1);
  const float tx = u - (float)x0, ty = v - (float)y0;
  for (int c = 0; c < 4; ++c) {
    __global const float* p = mean_ab + c * plane + MEAN_PAD;
    const float top = mix(p[y0 * pitch + x0], p[y0 * pitch + x1], tx);
    const float bot = mix(p[y1 * pitch + x0], p[y1 * pitch + x1], tx);
    m[c] = mix(top, bot, ty);
  }
#endif
  const float q = m[0] * I.x + m[1] * I.y + m[2] * I.z + m[3];
  const int c = categories[i] & 3;
  float mask = c == CAT_INFRONT ? 1.0f : c == CAT_BEHIND ? 0.0f : (q > 0.5f ? 1.0f : 0.0f);
#if LOCAL && SOFT
  if (c == CAT_PROCESS) {
    const float s = softness(i, INPUT_PASS);
    mask = (1.0f - s) * mask + s * clamp(q, 0.0f, 1.0f);
  }
#endif
  return (float4)(I, mask);
}

inline bool input_fast(int x0, int y, int w, int h, INPUT_ARGS) {
  return (SUBSAMPLE == 1 || SUBSAMPLE == 2) && x0 + VW <= w;
}

// 16 pixels from x0 (a multiple of 16): low-resolution columns x0/2 - 1 .. x0/2 + 8 hold
// every bilinear neighbour (the padding stands in for the clamp at the borders); even lanes
// sit 3/4 of the way to the next one, odd lanes 1/4.
__attribute__((always_inline)) inline void input_vec(int x0, int y, int w, int h, vf* out,
                                                     INPUT_ARGS) {
  const int i = y * w + x0;
  vf r, g, b;
  load_rgb16(rgb + 3 * i, &r, &g, &b);
  r *= 1.0f / 255.0f;
  g *= 1.0f / 255.0f;
  b *= 1.0f / 255.0f;
  vf m[4];
#if SUBSAMPLE == 1
  const int pitch1 = wl + 2 * MEAN_PAD;
  for (int c = 0; c < 4; ++c) m[c] = LOADF(mean_ab + (c * hl + y) * pitch1 + MEAN_PAD + x0);
#else
  const float v = clamp(((float)y + 0.5f) / SUBSAMPLE - 0.5f, 0.0f, (float)(hl - 1));
  const int y0 = (int)v, y1 = min(y0 + 1, hl - 1);
  const float ty = v - (float)y0;
  const vf tx = (vf)(0.75f, 0.25f, 0.75f, 0.25f, 0.75f, 0.25f, 0.75f, 0.25f, 0.75f, 0.25f, 0.75f,
                     0.25f, 0.75f, 0.25f, 0.75f, 0.25f);
  const int l = MEAN_PAD + x0 / 2 - 1, pitch = wl + 2 * MEAN_PAD, plane = pitch * hl;
  for (int c = 0; c < 4; ++c) {
    const vf top = LOADF(mean_ab + c * plane + y0 * pitch + l);
    const vf bot = LOADF(mean_ab + c * plane + y1 * pitch + l);
    const vf t =
        mix(__builtin_shufflevector(top, top, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8),
            __builtin_shufflevector(top, top, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9), tx);
    const vf u =
        mix(__builtin_shufflevector(bot, bot, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8),
            __builtin_shufflevector(bot, bot, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9), tx);
    m[c] = mix(t, u, ty);
  }
#endif
  const vf q = m[0] * r + m[1] * g + m[2] * b + m[3];
  const vi c = convert_int16(LOADU8(categories + i) & (uchar16)(3));
  vf mask = select((vf)(0.0f), (vf)(1.0f), q > 0.5f);
#if LOCAL && SOFT
  const vi process = c == CAT_PROCESS;
  if (any(process) && stats[0]) {
#if PRIOR > 0
    const uchar16 lo = LOADU8(prior + 2 * i), hi = LOADU8(prior + 2 * i + VW);
    const vf ni = convert_float16(__builtin_shufflevector(lo, hi, 0, 2, 4, 6, 8, 10, 12, 14, 16, 18,
                                                          20, 22, 24, 26, 28, 30)) +
                  1.0f;
    const vf nb = convert_float16(__builtin_shufflevector(lo, hi, 1, 3, 5, 7, 9, 11, 13, 15, 17, 19,
                                                          21, 23, 25, 27, 29, 31)) +
                  1.0f;
    const vf ambiguity = 4.0f * ni * nb / ((ni + nb) * (ni + nb));
#else
    const vf ambiguity = (vf)(1.0f);
#endif
    const vf s = select((vf)(0.0f), clamp(overlap[0] * ambiguity, 0.0f, 1.0f), process);
    mask = (1.0f - s) * mask + s * clamp(q, 0.0f, 1.0f);
  }
#endif
  mask = select(mask, (vf)(1.0f), c == CAT_INFRONT);
  mask = select(mask, (vf)(0.0f), c == CAT_BEHIND);
  out[0] = r;
  out[1] = g;
  out[2] = b;
  out[3] = mask;
}
#endif

// The input planes of 16 pixels from (x0, y): vectorised where the block lies inside, else
// pixel by pixel; 0 outside the image.
__attribute__((always_inline)) inline void input_row(int x0, int y, int w, int h, vf* v,
                                                     INPUT_ARGS) {
  if (input_fast(x0, y, w, h, INPUT_PASS)) {
    input_vec(x0, y, w, h, v, INPUT_PASS);
    return;
  }
  float t[4][VW];
  for (int k = 0; k < VW; ++k) {
    const float4 p = x0 + k < w ? input_pixel(x0 + k, y, w, h, INPUT_PASS) : (float4)(0.0f);
    t[0][k] = p.x;
    t[1][k] = p.y;
    t[2][k] = p.z;
    t[3][k] = p.w;
  }
  for (int c = 0; c < 4; ++c) v[c] = vload16(0, t[c]);
}

// ---- Outputs ------------------------------------------------------------------------------

#if INPUT_MODE == 1 && !LOCAL
#define KERNEL_INPUT_ARGS                                                                       \
  __global const uchar *rgb, __global const uchar *categories, __global const ushort *real_mm,  \
      __global const float *virtual_mm, __global const uint *hist, int min_samples, int full_w, \
      int full_h
#else
#define KERNEL_INPUT_ARGS INPUT_ARGS
#endif

#if OUTPUT_MODE == 0
#define OUTPUT_ARGS __global float* mean_out
#elif OUTPUT_MODE == 1
#define OUTPUT_ARGS __global const float *out_virtual_mm, __global float *alpha
#else
#define OUTPUT_ARGS __global float* alpha
#endif

// a = (Sigma + eps U)^-1 cov(I, p), b = mean_p - a . mean_I, from the window means s.
inline void solve_coefficients(const vf* s, float eps, vf* ab) {
  const vf mr = s[0], mg = s[1], mb = s[2], mp = s[3];
  const vf c0 = s[4] - mr * mp, c1 = s[5] - mg * mp, c2 = s[6] - mb * mp;
  const vf m00 = s[7] - mr * mr + eps, m01 = s[8] - mr * mg, m02 = s[9] - mr * mb;
  const vf m11 = s[10] - mg * mg + eps, m12 = s[11] - mg * mb, m22 = s[12] - mb * mb + eps;
  const vf i00 = m11 * m22 - m12 * m12, i01 = m02 * m12 - m01 * m22;
  const vf i02 = m01 * m12 - m02 * m11, i11 = m00 * m22 - m02 * m02;
  const vf i12 = m01 * m02 - m00 * m12, i22 = m00 * m11 - m01 * m01;
  const vf inv = 1.0f / (m00 * i00 + m01 * i01 + m02 * i02);
  ab[0] = (i00 * c0 + i01 * c1 + i02 * c2) * inv;
  ab[1] = (i01 * c0 + i11 * c1 + i12 * c2) * inv;
  ab[2] = (i02 * c0 + i12 * c1 + i22 * c2) * inv;
  ab[3] = mp - ab[0] * mr - ab[1] * mg - ab[2] * mb;
}

// 1 / pixels of the clipped windows of the 16 columns from x0 in row y.
// Pixels of the clipped windows of the 16 columns from x0 in row y.
inline vf window_counts(int x0, int y, int w, int h) {
  const vi x = lanes() + x0;
  const vi nx = min(w - 1, x + RADIUS) - max(0, x - RADIUS) + 1;
  return convert_float16(nx) * (float)window_count(y, h);
}

inline vf inverse_counts(int x0, int y, int w, int h) {
  return 1.0f / window_counts(x0, y, w, h);
}

// Pixels far from the virtual object: with CVF's inputs the filter's output there is known
// without filtering (docs/occlusion.md "Speed"). object_cols[2 y], [2 y + 1]: the columns
// [begin, end) of full-resolution row y (of n_rows) that hold its on-object pixels (begin >=
// end: none). Output row yo covers full rows [yo scale, yo scale + scale); the columns it
// computes are those within `reach` full-resolution pixels of an object pixel in the rows
// within `reach` of its own (reach < 0: every pixel). The host picks reach so that the output
// elsewhere is the constant written there: CVF's cost 0.5 off the object makes a = 0, b = 0.5
// (OUTPUT_MODE 0), and alpha is 0 off the object (OUTPUT_MODE 1). Returns the full-resolution
// columns [x, y) of the object pixels near output row yo (x >= y: none).
inline int2 object_columns(int yo, __global const int* object_cols, int n_rows, int scale,
                           int reach) {
  int2 r = (int2)(1 << 30, -(1 << 30));
  const int a = max(0, yo * scale - reach), b = min(n_rows - 1, yo * scale + scale - 1 + reach);
  for (int y = a; y <= b; ++y) {
    r.x = min(r.x, object_cols[2 * y]);
    r.y = max(r.y, object_cols[2 * y + 1]);
  }
  return r;
}

// CVF's output where no object is near (see above), over the padded row for OUTPUT_MODE 0.
#if OUTPUT_MODE == 0
#define CONSTANT_ROW(yo)                                                 \
  {                                                                      \
    const int pitch = w + 2 * MEAN_PAD;                                  \
    for (int c = 0; c < 4; ++c)                                          \
      for (int x = 0; x < pitch; ++x)                                    \
        mean_out[c * pitch * h + (yo)*pitch + x] = c == 3 ? 0.5f : 0.0f; \
  }
#elif OUTPUT_MODE == 1
#define CONSTANT_ROW(yo) \
  for (int x = 0; x < w; ++x) alpha[(yo)*w + x] = 0.0f;
#else
#define CONSTANT_ROW(yo)
#endif

__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void gf_strip(
    int w, int h, int strip_rows, float eps, __global float* scratch,
    __global const int* object_cols, int n_rows, int row_scale, int reach, KERNEL_INPUT_ARGS,
    OUTPUT_ARGS
#if TRACE
    ,
    __global float* trace_input
#endif
) {
  INPUT_SETUP
  const int srow = PAD + (w + VW - 1) / VW * VW + PAD;
  __global float* base = scratch + (size_t)get_group_id(1) * srow * (2 * 4 * NRING + 13 + 4);
  __global float* in_ring = base + PAD;                 // [NRING][4] rows
  __global float* col = in_ring + 4 * NRING * srow;     // [13] rows
  __global float* ab_ring = col + 13 * srow;            // [NRING][4] rows
  __global float* col_ab = ab_ring + 4 * NRING * srow;  // [4] rows
  const int plane = w * h;
  const int strip0 = (int)get_group_id(1) * strip_rows;
  const int strip1 = min(h, strip0 + strip_rows);
  // Spans of consecutive rows near the object, each streamed as a strip of its own (warm-up
  // included) over the columns near the object in any of its rows; the rest gets the constant.
  const int reach_l = reach / row_scale;  // in the filter's pixels
  for (int span = strip0; span < strip1;) {
    int2 cols = reach < 0 ? (int2)(0, w * row_scale)
                          : object_columns(span, object_cols, n_rows, row_scale, reach);
    if (cols.x >= cols.y) {
      CONSTANT_ROW(span);
      ++span;
      continue;
    }
    int span_end = span + 1;
    for (; span_end < strip1 && reach >= 0; ++span_end) {
      const int2 c = object_columns(span_end, object_cols, n_rows, row_scale, reach);
      if (c.x >= c.y) break;
      cols = (int2)(min(cols.x, c.x), max(cols.y, c.y));
    }
    if (reach < 0) span_end = strip1;
    const int y0 = span, y1 = span_end;
    span = span_end;
    // Output columns [out_lo, out_hi) are computed; the window sums are exact from 2 RADIUS + 1
    // columns inside the streamed columns [xa, xb) (zero columns stand in outside).
    const int out_lo = reach < 0 ? 0 : max(0, cols.x / row_scale - reach_l);
    const int out_hi = reach < 0 ? w : min(w, (cols.y + row_scale - 1) / row_scale + reach_l);
    const int xa = max(0, out_lo - 2 * RADIUS - 1) / VW * VW;
    const int xb = min(w, out_hi + 2 * RADIUS + 1);
    if (xa > 0 || xb < w) {
      for (int y = y0; y < y1; ++y) {
        CONSTANT_ROW(y)
      }
    }
    for (int k = -PAD; k < 13 * srow - PAD; ++k) col[k] = 0.0f;
    for (int k = -PAD; k < 4 * srow - PAD; ++k) col_ab[k] = 0.0f;

    // Input rows from y0 - 2 RADIUS on (earlier rows never enter); coefficient rows from
    // y0 - RADIUS (earlier ones are stored as 0); output rows y0 .. y1 - 1.
    const int first_in = y0 - 2 * RADIUS, first_ab = y0 - RADIUS;
    for (int t = y0 - 3 * RADIUS; t < y1 + RADIUS; ++t) {
      // 1. Row t + RADIUS enters the moment sums, row t - RADIUS - 1 leaves.
      const int yi = t + RADIUS;
      const bool leave_in = t - RADIUS - 1 >= first_in;
      __global float* ring_in = in_ring + ring_slot(yi) * 4 * srow;
      __global const float* ring_out = in_ring + ring_slot(t - RADIUS - 1) * 4 * srow;
      // 2. Coefficients of row t (0 outside the image and before first_ab).
      const bool ab_valid = t >= first_ab && t >= 0 && t < h;
      const bool leave_ab = t - 2 * RADIUS - 1 >= y0 - 3 * RADIUS;
      __global float* ab_in = ab_ring + ring_slot(t) * 4 * srow;
      __global const float* ab_out = ab_ring + ring_slot(t - 2 * RADIUS - 1) * 4 * srow;
      vf carry[13];
#pragma unroll
      for (int c = 0; c < 13; ++c) carry[c] = (vf)(0.0f);
      // 3. Output row t - RADIUS: window means of (a, b), applied to the guide.
      const int yo = t - RADIUS;
      const bool out_row = yo >= y0;
      __global const float* guide = in_ring + ring_slot(yo) * 4 * srow;
      vf carry_ab[4] = {(vf)(0.0f), (vf)(0.0f), (vf)(0.0f), (vf)(0.0f)};

      // One pass along the row: step 2 runs one vector behind step 1 and step 3 one behind
      // step 2, so each reads column sums (up to 16 columns ahead) that are already updated,
      // while they are still in the L1 cache.
      for (int x0 = xa; x0 < xb + 2 * VW; x0 += VW) {
        if (x0 < xb) {
          vf v[4] = {(vf)(0.0f), (vf)(0.0f), (vf)(0.0f), (vf)(0.0f)};
          if (yi >= 0 && yi < h) input_row(x0, yi, w, h, v, INPUT_PASS);
#if TRACE
          if (yi >= y0 && yi < y1)
            for (int c = 0; c < 4; ++c) store_row(trace_input + c * plane + yi * w, x0, w, v[c]);
#endif
          vf o[4] = {(vf)(0.0f), (vf)(0.0f), (vf)(0.0f), (vf)(0.0f)};
          for (int c = 0; c < 4; ++c) {
            STOREF(ring_in + c * srow + x0, v[c]);
            if (leave_in) o[c] = LOADF(ring_out + c * srow + x0);
          }
          const vf m[13] = {v[0] - o[0],
                            v[1] - o[1],
                            v[2] - o[2],
                            v[3] - o[3],
                            v[0] * v[3] - o[0] * o[3],
                            v[1] * v[3] - o[1] * o[3],
                            v[2] * v[3] - o[2] * o[3],
                            v[0] * v[0] - o[0] * o[0],
                            v[0] * v[1] - o[0] * o[1],
                            v[0] * v[2] - o[0] * o[2],
                            v[1] * v[1] - o[1] * o[1],
                            v[1] * v[2] - o[1] * o[2],
                            v[2] * v[2] - o[2] * o[2]};
#pragma unroll
          for (int c = 0; c < 13; ++c) {
            __global float* p = col + c * srow + x0;
            STOREF(p, LOADF(p) + m[c]);
          }
        }

        const int x2 = x0 - VW;
        if (x2 < xb && (ab_valid || x2 >= xa)) {
          vf ab[4] = {(vf)(0.0f), (vf)(0.0f), (vf)(0.0f), (vf)(0.0f)};
          if (ab_valid) {
            vf s[13];
#pragma unroll
            for (int c = 0; c < 13; ++c) s[c] = window_sums(col + c * srow, x2, &carry[c]);
            if (x2 >= xa) {
              const vf n = window_counts(x2, t, w, h);
#if INPUT_MODE != 0
              // CVF's inputs lie in [0, 1], so a window sum of 0 or of n means p is constant
              // over the window: then cov(I, p) = 0, a = 0 and b = p exactly, which is most of
              // the frame (off the object and inside known regions); the solve is skipped there.
              const vi flat = s[3] == 0.0f || s[3] == n;
#else
              const vi flat = (vi)(0);
#endif
              const vf inv_n = 1.0f / n;
#pragma unroll
              for (int c = 0; c < 13; ++c) s[c] *= inv_n;
              if (!all(flat)) solve_coefficients(s, eps, ab);
              ab[0] = select(ab[0], (vf)(0.0f), flat);
              ab[1] = select(ab[1], (vf)(0.0f), flat);
              ab[2] = select(ab[2], (vf)(0.0f), flat);
              ab[3] = select(ab[3], s[3], flat);
              const vi inside = lanes() + x2 < w;
              for (int c = 0; c < 4; ++c) ab[c] = select((vf)(0.0f), ab[c], inside);
            }
          }
          if (x2 >= xa) {
            for (int c = 0; c < 4; ++c) {
              STOREF(ab_in + c * srow + x2, ab[c]);
              const vf o = leave_ab ? LOADF(ab_out + c * srow + x2) : (vf)(0.0f);
              __global float* p = col_ab + c * srow + x2;
              STOREF(p, LOADF(p) + ab[c] - o);
            }
          }
        }

        const int x3 = x0 - 2 * VW;
        if (!out_row || x3 < xa - VW || x3 >= xb) continue;
        vf m[4];
#pragma unroll
        for (int c = 0; c < 4; ++c) m[c] = window_sums(col_ab + c * srow, x3, &carry_ab[c]);
        if (x3 < xa) continue;
        const vf inv_n = inverse_counts(x3, yo, w, h);
        for (int c = 0; c < 4; ++c) m[c] *= inv_n;
#if OUTPUT_MODE == 0
        const int pitch = w + 2 * MEAN_PAD;
        // Near the streamed range's ends the sums miss columns: the constant holds there.
        const vi near = lanes() + x3 >= out_lo && lanes() + x3 < out_hi;
        for (int c = 0; c < 4; ++c) m[c] = select((vf)(c == 3 ? 0.5f : 0.0f), m[c], near);
        for (int c = 0; c < 4; ++c) {
          __global float* row = mean_out + c * pitch * h + yo * pitch + MEAN_PAD;
          store_row(row, x3, w, m[c]);
          float tm[VW];
          vstore16(m[c], 0, tm);
          if (x3 == 0) STOREF(row - MEAN_PAD, (vf)(tm[0]));
          if (x3 + VW >= w) STOREF(row + w, (vf)(tm[w - 1 - x3]));
        }
#else
        const vf q = m[0] * LOADF(guide + x3) + m[1] * LOADF(guide + srow + x3) +
                     m[2] * LOADF(guide + 2 * srow + x3) + m[3];
#if OUTPUT_MODE == 1
        const vf vd = load_row(out_virtual_mm + yo * w, x3, w);
        store_row(alpha + yo * w, x3, w,
                  select((vf)(0.0f), clamp(1.0f - q, 0.0f, 1.0f), vd > 0.0f));
#else
        store_row(alpha + yo * w, x3, w, q);
#endif
#endif
      }
    }
  }
}
