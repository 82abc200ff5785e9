// Occluders the depth sensor cannot see (near_occluder_reference.hpp has the method): the
// object's hole and behind histograms (the behind ones per tile too), then q per pixel and the
// posterior cap on the pixels without depth. BINS (per channel) and TILE (px) are -D options.
#pragma OPENCL FP_CONTRACT OFF

#define NBINS (BINS * BINS * BINS)

inline int colour_bin3(uchar3 c) {
  return ((c.x * BINS / 256) * BINS + c.y * BINS / 256) * BINS + c.z * BINS / 256;
}

// hist: NBINS hole counts, NBINS behind counts, the hole and behind totals, then per tile
// NBINS behind counts, then per tile the behind total; zeroed by the host.
__kernel void near_occluder_histograms(__global const uchar* colour, __global const ushort* real_mm,
                                       __global const float* virtual_mm, int w, int h, int tiles_x,
                                       float tolerance_mm, __global uint* hist) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const float v = virtual_mm[i];
  if (!(v > 0.0f)) return;
  const ushort r = real_mm[i];
  const int b = colour_bin3(vload3(i, colour));
  if (r == 0) {
    atomic_inc(hist + b);
    atomic_inc(hist + 2 * NBINS);
  } else if ((float)r - v > tolerance_mm) {
    const int t = (y / TILE) * tiles_x + x / TILE;
    const int tiles = tiles_x * ((h + TILE - 1) / TILE);
    atomic_inc(hist + NBINS + b);
    atomic_inc(hist + 2 * NBINS + 1);
    atomic_inc(hist + 2 * NBINS + 2 + t * NBINS + b);
    atomic_inc(hist + 2 * NBINS + 2 + tiles * NBINS + t);
  }
}

// q of near_occluder_reference.hpp per pixel: 1 on known depth, -1 off the object.
__kernel void near_occluder_background(__global const uchar* colour, __global const ushort* real_mm,
                                       __global const float* virtual_mm, int w, int h, int tiles_x,
                                       uint min_samples, __global const uint* hist,
                                       __global float* q) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  if (!(virtual_mm[i] > 0.0f)) {
    q[i] = -1.0f;
    return;
  }
  const uint hole_total = hist[2 * NBINS], behind_total = hist[2 * NBINS + 1];
  if (real_mm[i] != 0 || hole_total < min_samples || behind_total < min_samples) {
    q[i] = 1.0f;
    return;
  }
  const int b = colour_bin3(vload3(i, colour));
  const float p_global = ((float)hist[NBINS + b] + 1.0f) / ((float)behind_total + (float)NBINS);
  const int tiles_y = (h + TILE - 1) / TILE, tiles = tiles_x * tiles_y;
  const int tx = x / TILE, ty = y / TILE;
  __global const uint* tile_hist = hist + 2 * NBINS + 2;
  float n = 0.0f, total = 0.0f;
  for (int j = max(0, ty - 1); j <= min(tiles_y - 1, ty + 1); ++j)
    for (int k = max(0, tx - 1); k <= min(tiles_x - 1, tx + 1); ++k) {
      const int t = j * tiles_x + k;
      n += (float)tile_hist[t * NBINS + b];
      total += (float)tile_hist[tiles * NBINS + t];
    }
  const float shrink = (float)min_samples;
  const float p_behind = (n + shrink * p_global) / (total + shrink);
  const float p_hole = ((float)hist[b] + 1.0f) / ((float)hole_total + (float)NBINS);
  q[i] = fmin(1.0f, p_behind / p_hole);
}

// The neighbourhood's mean nearness and the posterior cap on pixels without depth.
__kernel void near_occluder_apply(__global const ushort* real_mm, __global const float* q, int w,
                                  int h, int radius, __global float* alpha) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= w || y >= h) return;
  const int i = y * w + x;
  const float qc = q[i];
  if (qc < 0.0f || real_mm[i] != 0 || qc >= 1.0f) return;
  float near = 0.0f, n = 0.0f;
  for (int yy = max(0, y - radius); yy <= min(h - 1, y + radius); ++yy)
    for (int xx = max(0, x - radius); xx <= min(w - 1, x + radius); ++xx) {
      const float v = q[yy * w + xx];
      if (v < 0.0f) continue;
      near += 1.0f - v;
      n += 1.0f;
    }
  const float mean = (near + 1.0f) / (n + 2.0f);
  const float keep = qc * (1.0f - mean);
  const float cap = keep / (keep + (1.0f - qc) * mean);
  alpha[i] = fmin(alpha[i], cap);
}
