// Cost-volume-filtering occlusion (thesis ch. 3), the tile layout for GPUs: the per-pixel steps
// around the two-pass tile guided filter of guided_filter.cl, with cvf_categorise.cl for the
// categories and band. CPU devices use the row-streaming kernels (cvf.cl, cvf_guided.cl), which
// run one work-item per strip of rows and would leave a GPU idle. The device side of
// cvf_reference.cpp; docs/occlusion.md has the conventions.
//
// Build options: -DBINS=b (histogram bins per channel), -DSUBSAMPLE=s (the wide filter's),
// -DLOCAL=0/1 (1: the shipped CVF with local colour models, whose costs and softness
// cvf_local_histogram.cl computes; 0: the thesis's CVF).

#define CAT_IGNORE 0
#define CAT_BEHIND 1
#define CAT_INFRONT 2
#define CAT_PROCESS 3
#define NBINS (BINS * BINS * BINS)
#ifndef LOCAL
#define LOCAL 0
#endif

inline int colour_bin(uchar r, uchar g, uchar b) {
  return ((r * BINS / 256) * BINS + g * BINS / 256) * BINS + b * BINS / 256;
}

// Colour models: joint RGB histograms of infront and behind pixels in the band. Each
// work-group counts into local memory, then adds to the global counts
// (hist[0..NBINS) infront, hist[NBINS..2 NBINS) behind), which start at zero.
__kernel void cvf_histogram(__global const uchar* rgb, __global const uchar* categories,
                            __global const uchar* band, int n, __global uint* hist) {
  __local uint local_hist[2 * NBINS];
  for (int k = get_local_id(0); k < 2 * NBINS; k += get_local_size(0)) local_hist[k] = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int i = get_global_id(0); i < n; i += get_global_size(0)) {
    const uchar c = categories[i];
    if (!band[i] || (c != CAT_INFRONT && c != CAT_BEHIND)) continue;
    const int bin = colour_bin(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
    atomic_inc(&local_hist[(c == CAT_INFRONT ? 0 : NBINS) + bin]);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int k = get_local_id(0); k < 2 * NBINS; k += get_local_size(0))
    if (local_hist[k]) atomic_add(&hist[k], local_hist[k]);
}

// Cost of one pixel (thesis 3.3.3; cvf_cost() in cvf_reference.cpp).
inline float pixel_cost(int c, int bin, __local const uint* h, float inv_in, float inv_be,
                        int valid, ushort real_mm, float virtual_mm) {
  if (c == CAT_INFRONT) return 1.0f;
  if (c == CAT_BEHIND) return 0.0f;
  if (c == CAT_IGNORE) return 0.5f;
  if (!valid) return real_mm == 0 ? 0.5f : ((float)real_mm < virtual_mm ? 1.0f : 0.0f);
  const float p_in = (float)h[bin] * inv_in, p_be = (float)h[NBINS + bin] * inv_be;
  return p_in + p_be > 0.0f ? p_in / (p_in + p_be) : 0.5f;
}

// Packs the wide filter's input: (r, g, b, cost) averaged over SUBSAMPLE^2 blocks (the
// in-image part), rgb in [0, 1]. One work-item per output pixel.
__kernel void cvf_cost_pack(__global const uchar* rgb, __global const ushort* real_mm,
                            __global const float* virtual_mm, __global const uchar* categories,
                            __global const uint* hist, int min_samples, int w, int h, int wl,
                            int hl, __global float4* packed) {
  __local uint lh[2 * NBINS];
  __local uint totals[2];
  const int lid = get_local_id(1) * get_local_size(0) + get_local_id(0);
  const int lsize = get_local_size(0) * get_local_size(1);
  for (int k = lid; k < 2 * NBINS; k += lsize) lh[k] = hist[k];
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 0) {
    uint a = 0, b = 0;
    for (int k = 0; k < NBINS; ++k) {
      a += lh[k];
      b += lh[NBINS + k];
    }
    totals[0] = a;
    totals[1] = b;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const int xl = get_global_id(0), yl = get_global_id(1);
  if (xl >= wl || yl >= hl) return;
  const int valid = totals[0] >= (uint)min_samples && totals[1] >= (uint)min_samples;
  const float inv_in = valid ? 1.0f / (float)totals[0] : 0.0f;
  const float inv_be = valid ? 1.0f / (float)totals[1] : 0.0f;
  float4 sum = (float4)(0.0f);
  int n = 0;
  for (int dy = 0; dy < SUBSAMPLE; ++dy)
    for (int dx = 0; dx < SUBSAMPLE; ++dx) {
      const int x = xl * SUBSAMPLE + dx, y = yl * SUBSAMPLE + dy;
      if (x >= w || y >= h) continue;
      const int i = y * w + x;
      const uchar r = rgb[3 * i], g = rgb[3 * i + 1], b = rgb[3 * i + 2];
      const float cost = pixel_cost(categories[i], colour_bin(r, g, b), lh, inv_in, inv_be, valid,
                                    real_mm[i], virtual_mm[i]);
      sum += (float4)((float)r, (float)g, (float)b, 0.0f) * (1.0f / 255.0f) +
             (float4)(0.0f, 0.0f, 0.0f, cost);
      ++n;
    }
  packed[yl * wl + xl] = sum / (float)n;
}

// Packs the wide filter's input from a cost image (the shipped CVF: cvf_local_histogram.cl
// wrote it): (r, g, b, cost) averaged over SUBSAMPLE^2 blocks, rgb in [0, 1].
__kernel void cvf_cost_image_pack(__global const uchar* rgb, __global const float* cost, int w,
                                  int h, int wl, int hl, __global float4* packed) {
  const int xl = get_global_id(0), yl = get_global_id(1);
  if (xl >= wl || yl >= hl) return;
  float4 sum = (float4)(0.0f);
  int n = 0;
  for (int dy = 0; dy < SUBSAMPLE; ++dy)
    for (int dx = 0; dx < SUBSAMPLE; ++dx) {
      const int x = xl * SUBSAMPLE + dx, y = yl * SUBSAMPLE + dy;
      if (x >= w || y >= h) continue;
      const int i = y * w + x;
      sum += (float4)((float)rgb[3 * i], (float)rgb[3 * i + 1], (float)rgb[3 * i + 2], 0.0f) *
                 (1.0f / 255.0f) +
             (float4)(0.0f, 0.0f, 0.0f, cost[i]);
      ++n;
    }
  packed[yl * wl + xl] = sum / (float)n;
}

#if LOCAL
#define SOFTNESS_ARG , __global const float* softness
#else
#define SOFTNESS_ARG
#endif

// The wide filter's output at full resolution (mean a, b upsampled bilinearly when
// SUBSAMPLE > 1), thresholded: infront 1, behind 0, else q > 0.5, and with LOCAL blended with
// the soft q by the pixel's softness s (0 off process pixels). Packs (r, g, b, mask) for the
// feather filter.
__kernel void cvf_mask_pack(__global const uchar* rgb, __global const uchar* categories,
                            __global const float4* mean_ab, int w, int h, int wl, int hl,
                            __global float4* packed SOFTNESS_ARG) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const float4 I = (float4)((float)rgb[3 * i], (float)rgb[3 * i + 1], (float)rgb[3 * i + 2], 0.0f) *
                   (1.0f / 255.0f);
  float4 m;
#if SUBSAMPLE == 1
  m = mean_ab[i];
#else
  const float u = clamp(((float)x + 0.5f) / SUBSAMPLE - 0.5f, 0.0f, (float)(wl - 1));
  const float v = clamp(((float)y + 0.5f) / SUBSAMPLE - 0.5f, 0.0f, (float)(hl - 1));
  const int x0 = (int)u, y0 = (int)v;
  const int x1 = min(x0 + 1, wl - 1), y1 = min(y0 + 1, hl - 1);
  const float tx = u - (float)x0, ty = v - (float)y0;
  const float4 top = mix(mean_ab[y0 * wl + x0], mean_ab[y0 * wl + x1], tx);
  const float4 bot = mix(mean_ab[y1 * wl + x0], mean_ab[y1 * wl + x1], tx);
  m = mix(top, bot, ty);
#endif
  const float q = m.x * I.x + m.y * I.y + m.z * I.z + m.w;
  const uchar c = categories[i];
  float mask = c == CAT_INFRONT ? 1.0f : c == CAT_BEHIND ? 0.0f : (q > 0.5f ? 1.0f : 0.0f);
#if LOCAL
  if (c == CAT_PROCESS) mask = (1.0f - softness[i]) * mask + softness[i] * clamp(q, 0.0f, 1.0f);
#endif
  packed[i] = (float4)(I.x, I.y, I.z, mask);
}
