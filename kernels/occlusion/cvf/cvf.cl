// Cost-volume-filtering occlusion (thesis ch. 3), first stage as ONE row-streaming kernel:
// depth test, erosion of the infront/behind border, the band around the process region and
// the colour histograms of the known pixels in the band. The device side of
// categorise_reference.cpp and histogram_reference.cpp; docs/occlusion.md has the
// conventions, cvf_vector.cl (prepended) the vector helpers and the strip layout.
//
// One work-item per strip of rows, the whole width in float16 vectors. Per row t it
//   1. takes the raw depth test of row t + EROSION into a ring and the running column counts
//      of infront and behind pixels over 2 EROSION + 1 rows;
//   2. turns them into window counts along the row (running sums, cvf_vector.cl): row t's
//      infront pixels with a behind pixel in their window, and the reverse, become process;
//      the categories go into a second ring with the running column count of process pixels;
//   3. the same along the row over 2 BAND + 1 columns gives the band of row t - BAND; writes
//      that row's categories (bits 0-1) with the band (bit 2), and counts the colours of its
//      infront and behind pixels in the band into the work-group's histograms.
// Counts are small integers, exact in float.
//
// With LOCAL=1 (the shipped CVF, local colour models: docs/occlusion.md) it also
//   2b. keeps running column counts of the ERODED infront and behind pixels over 2 PRIOR + 1
//      rows and writes, per pixel of row t - PRIOR, the counts of its (2 PRIOR + 1)^2 window
//      (the local prior: uchar2 (infront, behind) per pixel);
//   3b. counts each known band pixel's colour into its TILE x TILE tile's histograms as well,
//      per row of tiles in the strip's scratch, added atomically to `tile_hist` when the row
//      of tiles (or the strip) ends.
//
// Build options: -DEROSION=e -DBAND=b (radii, <= 16), -DBINS=n (histogram bins per channel),
// -DLOCAL=0/1, and with LOCAL=1 -DTILE=t (tile side, px) -DPRIOR=r (prior radius, <= 7).

#define CAT_IGNORE 0
#define CAT_BEHIND 1
#define CAT_INFRONT 2
#define CAT_PROCESS 3
#define NBINS (BINS * BINS * BINS)
#ifndef LOCAL
#define LOCAL 0
#endif
#if !LOCAL
#undef PRIOR
#define PRIOR 0
#endif
// Rows of eroded categories kept: the band's window and the prior's.
#define MAXR (BAND > PRIOR ? BAND : PRIOR)
#define NRAW (2 * EROSION + 2)
#define NCAT (2 * MAXR + 2)
#define BAND_BIT 4

inline int slot(int y, int n) {
  return ((y % n) + n) % n;
}

// Raw depth test of 16 pixels from index i (x0 is their column): 0 off the object,
// 3 unknown or within the tolerance, 2 real in front, 1 real behind.
inline vf raw_categories(__global const ushort* real_mm, __global const float* virtual_mm, int i,
                         int x0, int w, float tolerance_mm) {
  vf r, v;
  if (x0 + VW <= w) {
    r = convert_float16(LOADU16(real_mm + i));
    v = LOADF(virtual_mm + i);
  } else {
    float tr[VW], tv[VW];
    for (int k = 0; k < VW; ++k) {
      tr[k] = x0 + k < w ? (float)real_mm[i + k] : 0.0f;
      tv[k] = x0 + k < w ? virtual_mm[i + k] : 0.0f;
    }
    r = vload16(0, tr);
    v = vload16(0, tv);
  }
  vf c = select((vf)(CAT_BEHIND), (vf)(CAT_INFRONT), r < v);
  // depth_tolerance_mm() of cvf_params.hpp (TOL_QUAD, TOL_Z0: -D options), per pixel.
  const vf d = v - (vf)(TOL_Z0);
  vf q = d * d;
  q = (vf)(TOL_QUAD) * q;
  const vf tolerance = (vf)(tolerance_mm) + q;
  c = select(c, (vf)(CAT_PROCESS), r == 0.0f || fabs(r - v) <= tolerance);
  return select((vf)(CAT_IGNORE), c, v > 0.0f);
}

#if LOCAL
#define LOCAL_ARGS , int tiles_x, __global uint *tile_hist, __global uchar *prior
#else
#define LOCAL_ARGS
#endif

// Scratch per strip: NRAW raw rows, 2 count rows, NCAT category rows, 1 count row; with LOCAL
// 2 prior count rows and the row of tiles' histograms (tiles_x x 2 NBINS counts).
__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void cvf_classify(
    int w, int h, int strip_rows, int row_begin, int row_end, float tolerance_mm,
    __global float* scratch,
    __global const ushort* real_mm, __global const float* virtual_mm, __global const uchar* rgb,
    __global uchar* categories, __global uint* hist, __global int* object_cols LOCAL_ARGS) {
  __local uint local_hist[2 * NBINS];
  for (int k = 0; k < 2 * NBINS; ++k) local_hist[k] = 0;
  const int srow = PAD + (w + VW - 1) / VW * VW + PAD;
#if LOCAL
  const size_t strip_floats = (size_t)srow * (NRAW + 5 + NCAT) + (size_t)tiles_x * 2 * NBINS;
#else
  const size_t strip_floats = (size_t)srow * (NRAW + 3 + NCAT);
#endif
  __global float* raw = scratch + (size_t)get_group_id(1) * strip_floats + PAD;
  __global float* count_in = raw + NRAW * srow;
  __global float* count_be = count_in + srow;
  __global float* cat = count_be + srow;
  __global float* count_pr = cat + NCAT * srow;
  for (int k = -PAD; k < srow - PAD; ++k) count_in[k] = count_be[k] = count_pr[k] = 0.0f;
#if LOCAL
  __global float* prior_in = count_pr + srow;
  __global float* prior_be = prior_in + srow;
  __global uint* tile_row = (__global uint*)(prior_be + srow - PAD);
  for (int k = -PAD; k < srow - PAD; ++k) prior_in[k] = prior_be[k] = 0.0f;
  for (int k = 0; k < tiles_x * 2 * NBINS; ++k) tile_row[k] = 0;
#endif
  // Rows [row_begin, row_end) only: the host fills the others' outputs (CvfMatte).
  const int y0 = row_begin + (int)get_group_id(1) * strip_rows;
  const int y1 = min(row_end, y0 + strip_rows);

  const int first_cat = y0 - MAXR, first_raw = first_cat - EROSION;
  const int start = first_raw - EROSION;
  for (int t = start; t < y1 + MAXR; ++t) {
    // 1. Raw row t + EROSION enters the column counts, row t - EROSION - 1 leaves.
    {
      const int ye = t + EROSION;
      const bool leave = t - EROSION - 1 >= first_raw;
      __global float* in = raw + slot(ye, NRAW) * srow;
      __global const float* out = raw + slot(t - EROSION - 1, NRAW) * srow;
      for (int x0 = 0; x0 < w; x0 += VW) {
        const vf c = ye >= 0 && ye < h
                         ? raw_categories(real_mm, virtual_mm, ye * w + x0, x0, w, tolerance_mm)
                         : (vf)(0.0f);
        STOREF(in + x0, c);
        const vf o = leave ? LOADF(out + x0) : (vf)(0.0f);
        STOREF(count_in + x0, LOADF(count_in + x0) +
                                  select((vf)(0.0f), (vf)(1.0f), c == CAT_INFRONT) -
                                  select((vf)(0.0f), (vf)(1.0f), o == CAT_INFRONT));
        STOREF(count_be + x0, LOADF(count_be + x0) +
                                  select((vf)(0.0f), (vf)(1.0f), c == CAT_BEHIND) -
                                  select((vf)(0.0f), (vf)(1.0f), o == CAT_BEHIND));
      }
    }
    // 2. Erosion of row t (thesis 3.3.1; process pixels do not erode).
    {
      const bool valid = t >= first_cat;
      const bool leave = t - 2 * BAND - 1 >= start;
      __global const float* own = raw + slot(t, NRAW) * srow;
      __global float* in = cat + slot(t, NCAT) * srow;
      __global const float* out = cat + slot(t - 2 * BAND - 1, NCAT) * srow;
      vf carry_in = (vf)(0.0f), carry_be = (vf)(0.0f);
      for (int x0 = -VW; x0 < w; x0 += VW) {
        vf c = (vf)(0.0f);
        if (valid) {
          const vf near_in = running_window_sums(count_in, x0, EROSION, &carry_in);
          const vf near_be = running_window_sums(count_be, x0, EROSION, &carry_be);
          if (x0 < 0) continue;
          c = LOADF(own + x0);
          c = select(c, (vf)(CAT_PROCESS),
                     (c == CAT_INFRONT && near_be > 0.5f) || (c == CAT_BEHIND && near_in > 0.5f));
        } else if (x0 < 0) {
          continue;
        }
        STOREF(in + x0, c);
        const vf o = leave ? LOADF(out + x0) : (vf)(0.0f);
        STOREF(count_pr + x0, LOADF(count_pr + x0) +
                                  select((vf)(0.0f), (vf)(1.0f), c == CAT_PROCESS) -
                                  select((vf)(0.0f), (vf)(1.0f), o == CAT_PROCESS));
      }
    }
#if LOCAL && PRIOR > 0
    // 2b. The local prior: eroded row t enters its column counts, row t - 2 PRIOR - 1 leaves;
    // the window counts of row t - PRIOR go out as (infront, behind) bytes.
    {
      const bool leave = t - 2 * PRIOR - 1 >= start;
      __global const float* in = cat + slot(t, NCAT) * srow;
      __global const float* out = cat + slot(t - 2 * PRIOR - 1, NCAT) * srow;
      for (int x0 = 0; x0 < w; x0 += VW) {
        const vf c = LOADF(in + x0);
        const vf o = leave ? LOADF(out + x0) : (vf)(0.0f);
        STOREF(prior_in + x0, LOADF(prior_in + x0) +
                                  select((vf)(0.0f), (vf)(1.0f), c == CAT_INFRONT) -
                                  select((vf)(0.0f), (vf)(1.0f), o == CAT_INFRONT));
        STOREF(prior_be + x0, LOADF(prior_be + x0) +
                                  select((vf)(0.0f), (vf)(1.0f), c == CAT_BEHIND) -
                                  select((vf)(0.0f), (vf)(1.0f), o == CAT_BEHIND));
      }
      const int yp = t - PRIOR;
      if (yp >= y0 && yp < y1) {
        vf carry_in = (vf)(0.0f), carry_be = (vf)(0.0f);
        for (int x0 = -VW; x0 < w; x0 += VW) {
          const vf n_in = running_window_sums(prior_in, x0, PRIOR, &carry_in);
          const vf n_be = running_window_sums(prior_be, x0, PRIOR, &carry_be);
          if (x0 < 0) continue;
          const uchar16 a = convert_uchar16(n_in), b = convert_uchar16(n_be);
          const uchar16 lo =
              __builtin_shufflevector(a, b, 0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
          const uchar16 hi = __builtin_shufflevector(a, b, 8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13,
                                                     29, 14, 30, 15, 31);
          __global uchar* dst = prior + 2 * ((size_t)yp * w + x0);
          if (x0 + VW <= w) {
            STOREU8(dst, lo);
            STOREU8(dst + VW, hi);
          } else {
            uchar t8[2 * VW];
            vstore16(lo, 0, t8);
            vstore16(hi, 1, t8);
            for (int k = 0; k < 2 * (w - x0); ++k) dst[k] = t8[k];
          }
        }
      }
    }
#endif
    // 3. Band of row t - BAND (thesis 3.3.2), its categories out, its colours counted.
    const int yb = t - BAND;
    if (yb < y0 || yb >= y1) continue;
    __global const float* row = cat + slot(yb, NCAT) * srow;
    vf carry = (vf)(0.0f);
    int object_begin = w, object_end = 0;
    for (int x0 = -VW; x0 < w; x0 += VW) {
      const vf near_pr = running_window_sums(count_pr, x0, BAND, &carry);
      if (x0 < 0) continue;
      const vf c = LOADF(row + x0);
      if (any(c != (vf)(CAT_IGNORE))) {
        object_begin = min(object_begin, x0);
        object_end = min(w, x0 + VW);
      }
      const vi band = near_pr > 0.5f;
      const uchar16 byte = convert_uchar16(c) + convert_uchar16(-band) * (uchar16)(BAND_BIT);
      const int i = yb * w + x0;
      if (x0 + VW <= w) {
        STOREU8(categories + i, byte);
      } else {
        uchar t8[VW];
        vstore16(byte, 0, t8);
        for (int k = 0; x0 + k < w; ++k) categories[i + k] = t8[k];
      }
      const vi known = band & (c == CAT_INFRONT || c == CAT_BEHIND);
      if (!any(known)) continue;
      int bins[VW], flags[VW];
      if (x0 + VW <= w) {
        vf r, g, b;
        load_rgb16(rgb + 3 * i, &r, &g, &b);
        const vi bin =
            ((convert_int16(r) * BINS / 256) * BINS + convert_int16(g) * BINS / 256) * BINS +
            convert_int16(b) * BINS / 256;
        vstore16(bin, 0, bins);
      } else {
        for (int k = 0; k < VW; ++k) {
          const int j = 3 * (i + min(k, w - 1 - x0));
          bins[k] = ((rgb[j] * BINS / 256) * BINS + rgb[j + 1] * BINS / 256) * BINS +
                    rgb[j + 2] * BINS / 256;
        }
      }
      vstore16(select((vi)(0), (vi)(NBINS), c == CAT_BEHIND) | (known & (vi)(1 << 30)), 0, flags);
      for (int k = 0; k < VW; ++k)
        if (flags[k] & (1 << 30)) {
          const int j = (flags[k] & ~(1 << 30)) + bins[k];
          local_hist[j]++;
#if LOCAL
          tile_row[(x0 + k) / TILE * 2 * NBINS + j]++;
#endif
        }
    }
    // The columns that hold the object (to 16 px): the filters skip what lies far from them
    // (cvf_guided.cl, object_columns()).
    object_cols[2 * yb] = object_begin;
    object_cols[2 * yb + 1] = object_end;
#if LOCAL
    // 3b. The row of tiles (or the strip) ends: its counts go to the tiles' histograms.
    if ((yb + 1) % TILE == 0 || yb == y1 - 1) {
      __global uint* dst = tile_hist + (size_t)(yb / TILE) * tiles_x * 2 * NBINS;
      for (int k = 0; k < tiles_x * 2 * NBINS; ++k)
        if (tile_row[k]) {
          atomic_add(&dst[k], tile_row[k]);
          tile_row[k] = 0;
        }
    }
#endif
  }
  // hist: infront counts [0, NBINS), behind [NBINS, 2 NBINS), then the two totals.
  uint total_in = 0, total_be = 0;
  for (int k = 0; k < NBINS; ++k) {
    total_in += local_hist[k];
    total_be += local_hist[NBINS + k];
    if (local_hist[k]) atomic_add(&hist[k], local_hist[k]);
    if (local_hist[NBINS + k]) atomic_add(&hist[NBINS + k], local_hist[NBINS + k]);
  }
  if (total_in) atomic_add(&hist[2 * NBINS], total_in);
  if (total_be) atomic_add(&hist[2 * NBINS + 1], total_be);
}
