// CVF with local colour models (docs/occlusion.md "Local colour models (proposed CVF
// change)"): the device side of local_costs_reference() in cvf_local_reference.cpp. Replaces
// CVF's histogram and cost steps; the wide filter then reads `cost`, and the threshold step
// blends with `softness`: mask = (1 - s) [wide > 0.5] + s clamp(wide, 0, 1).
//
// Build options: -DBINS=b (bins per channel, NBINS = b^3 <= 512), -DTILE=t (tile side, px),
// -DPRIOR_RADIUS=r (window of the local prior, 0 = none, at most 127), -DSOFT=0/1.

#define CAT_IGNORE 0
#define CAT_BEHIND 1
#define CAT_INFRONT 2
#define CAT_PROCESS 3
#define NBINS (BINS * BINS * BINS)

inline int colour_bin(uchar r, uchar g, uchar b) {
  return ((r * BINS / 256) * BINS + g * BINS / 256) * BINS + b * BINS / 256;
}

// One work-group per tile: counts the tile's band pixels into local memory, writes the tile's
// pair (tile_hist[tile][0..NBINS) infront, [NBINS..2 NBINS) behind) and adds it to the global
// pair `hist` (zeroed by the host), so the frame's model costs no second pass.
__kernel void cvf_local_tile_histogram(__global const uchar* rgb, __global const uchar* categories,
                                       __global const uchar* band, int w, int h,
                                       __global uint* tile_hist, __global uint* hist) {
  __local uint lh[2 * NBINS];
  const int lid = get_local_id(1) * get_local_size(0) + get_local_id(0);
  const int lsize = get_local_size(0) * get_local_size(1);
  for (int k = lid; k < 2 * NBINS; k += lsize) lh[k] = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  const int tx = get_group_id(0), ty = get_group_id(1);
  const int x_end = min(w, (tx + 1) * TILE), y_end = min(h, (ty + 1) * TILE);
  for (int y = ty * TILE + (int)get_local_id(1); y < y_end; y += (int)get_local_size(1))
    for (int x = tx * TILE + (int)get_local_id(0); x < x_end; x += (int)get_local_size(0)) {
      const int i = y * w + x;
      const uchar c = categories[i];
      if (!band[i] || (c != CAT_INFRONT && c != CAT_BEHIND)) continue;
      const int bin = colour_bin(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
      atomic_inc(&lh[(c == CAT_INFRONT ? 0 : NBINS) + bin]);
    }
  barrier(CLK_LOCAL_MEM_FENCE);
  __global uint* out = tile_hist + (size_t)(ty * get_num_groups(0) + tx) * 2 * NBINS;
  for (int k = lid; k < 2 * NBINS; k += lsize) {
    out[k] = lh[k];
    if (lh[k]) atomic_add(&hist[k], lh[k]);
  }
}

// One work-item per tile: the tile's likelihoods shrunk towards the Laplace-smoothed global
// ones with min_samples pseudo-counts (tile_likelihoods()). Work-item 0 also writes
// stats[0] = 1 when the global pair has >= min_samples per class (else the costs fall back to
// the depth test and nothing else is written) and overlap[0] = the global pair's
// Bhattacharyya coefficient (global_likelihoods().overlap[0], the softness's factor).
__kernel void cvf_local_likelihoods(__global const uint* tile_hist, __global const uint* hist,
                                    int tiles, int min_samples, __global float* lik,
                                    __global float* overlap, __global int* stats) {
  const int t = get_global_id(0);
  if (t >= tiles) return;
  uint g_in = 0, g_be = 0, n_in = 0, n_be = 0;
  __global const uint* th = tile_hist + (size_t)t * 2 * NBINS;
  for (int b = 0; b < NBINS; ++b) {
    g_in += hist[b];
    g_be += hist[NBINS + b];
    n_in += th[b];
    n_be += th[NBINS + b];
  }
  const int valid = g_in >= (uint)min_samples && g_be >= (uint)min_samples;
  if (t == 0) stats[0] = valid;
  if (!valid) return;
  const float m = (float)max(1, min_samples);
  const float gi_den = (float)g_in + (float)NBINS, gb_den = (float)g_be + (float)NBINS;
  const float ti_den = (float)n_in + m, tb_den = (float)n_be + m;
  __global float* out = lik + (size_t)t * 2 * NBINS;
  float bc = 0.0f;
  for (int b = 0; b < NBINS; ++b) {
    const float gi = ((float)hist[b] + 1.0f) / gi_den;
    const float gb = ((float)hist[NBINS + b] + 1.0f) / gb_den;
    out[b] = ((float)th[b] + m * gi) / ti_den;
    out[NBINS + b] = ((float)th[NBINS + b] + m * gb) / tb_den;
    bc += sqrt(gi * gb);
  }
  if (t == 0) overlap[0] = min(bc, 1.0f);
}

#if PRIOR_RADIUS > 0
// The prior's window counts, separably: per pixel the infront and behind pixels of its row
// window (the cost kernel sums 2r+1 of these down the column: 14 reads instead of 49).
__kernel void cvf_local_count_rows(__global const uchar* categories, int w, int h,
                                   __global uchar2* rows) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  __global const uchar* row = categories + (size_t)y * w;
  uchar n_in = 0, n_be = 0;
  for (int k = max(0, x - PRIOR_RADIUS); k <= min(w - 1, x + PRIOR_RADIUS); ++k) {
    n_in += row[k] == CAT_INFRONT;
    n_be += row[k] == CAT_BEHIND;
  }
  rows[(size_t)y * w + x] = (uchar2)(n_in, n_be);
}
#endif

// Tile centres at (t + 0.5) TILE; beyond the outermost centres the nearest one holds.
inline void blend_axis(int p, int tiles, int* t0, int* t1, float* f) {
  const float u = clamp(((float)p + 0.5f) / (float)TILE - 0.5f, 0.0f, (float)(tiles - 1));
  *t0 = min((int)u, tiles - 1);
  *t1 = min(*t0 + 1, tiles - 1);
  *f = u - (float)*t0;
}

// One work-item per pixel: CVF's cost for known pixels and without colour models; on process
// pixels the local posterior from the 4 nearest tiles' likelihoods and the window prior, and
// the softness s = global overlap x prior ambiguity (local_cost()).
__kernel void cvf_local_cost(__global const uchar* rgb, __global const ushort* real_mm,
                             __global const float* virtual_mm, __global const uchar* categories,
                             int w, int h, int tiles_x, int tiles_y, __global const float* lik,
                             __global const float* overlap, __global const int* stats,
                             __global const uchar2* rows, __global float* cost,
                             __global float* softness) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const uchar c = categories[i];
  float out_cost, out_soft = 0.0f;
  if (c == CAT_INFRONT) {
    out_cost = 1.0f;
  } else if (c == CAT_BEHIND) {
    out_cost = 0.0f;
  } else if (c == CAT_IGNORE) {
    out_cost = 0.5f;
  } else if (!stats[0]) {
    const ushort r = real_mm[i];
    out_cost = r == 0 ? 0.5f : ((float)r < virtual_mm[i] ? 1.0f : 0.0f);
  } else {
    const int bin = colour_bin(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
    int x0, x1, y0, y1;
    float fx, fy;
    blend_axis(x, tiles_x, &x0, &x1, &fx);
    blend_axis(y, tiles_y, &y0, &y1, &fy);
    const int tile[4] = {y0 * tiles_x + x0, y0 * tiles_x + x1, y1 * tiles_x + x0,
                         y1 * tiles_x + x1};
    const float wt[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    float p_in = 0.0f, p_be = 0.0f;
    for (int k = 0; k < 4; ++k) {
      __global const float* l = lik + (size_t)tile[k] * 2 * NBINS;
      p_in += wt[k] * l[bin];
      p_be += wt[k] * l[NBINS + bin];
    }
    float ambiguity = 1.0f;
#if PRIOR_RADIUS > 0
    int n_in = 0, n_be = 0;
    for (int j = max(0, y - PRIOR_RADIUS); j <= min(h - 1, y + PRIOR_RADIUS); ++j) {
      const uchar2 r = rows[(size_t)j * w + x];
      n_in += r.x;
      n_be += r.y;
    }
    const float ni = (float)n_in + 1.0f, nb = (float)n_be + 1.0f;
    p_in *= ni / (ni + nb);
    p_be *= nb / (ni + nb);
    ambiguity = 4.0f * ni * nb / ((ni + nb) * (ni + nb));
#endif
    out_cost = p_in + p_be > 0.0f ? p_in / (p_in + p_be) : 0.5f;
#if SOFT
    out_soft = clamp(overlap[0] * ambiguity, 0.0f, 1.0f);
#endif
  }
  cost[i] = out_cost;
  softness[i] = out_soft;
}
