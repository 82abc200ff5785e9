// The HDR surfel map on the device (surfel_map.hpp, docs/fusion.md "The surfel map on the
// device"); surfel_map_reference.cpp is the specification, rule for rule and operation for
// operation, so that the device takes the reference's decisions (contraction into fma off; the
// radial weights and the 8-bit linearisation come from the host's std:: functions as tables).
//
// The host prepends common/vector16.cl (vf, vi, LOADF, STOREF, lanes()).
//
// Surfels are a structure of arrays: FLOAT_PLANES float planes of `cap` entries (position,
// normal, radius, confidence, radiance), two long planes (created, last seen) and a byte of
// flags. Each pass over surfels reads a few planes only (the index map's projection reads
// the position, the stale test confidence and last seen), and PoCL vectorises loads of plain
// floats, not of float3 structs (docs/opencl.md "What PoCL vectorises").
//
// Why no atomics in the fuse: a surfel occupies one cell of the index map, and a cell belongs
// to exactly one depth pixel's INDEX_SCALE x INDEX_SCALE block, so at most one pixel can pick a
// surfel; the pixel's own search runs over its cells in the reference's row-major order.
#pragma OPENCL FP_CONTRACT OFF
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

#if !defined(INDEX_SCALE) || !defined(NORMAL_STEP) || !defined(SMOOTH_R) || !defined(PAD) || \
    !defined(BLOCK)
#error "surfel_map.cl needs -DINDEX_SCALE, -DNORMAL_STEP, -DSMOOTH_R, -DPAD and -DBLOCK"
#endif

#define P_X 0
#define P_Y 1
#define P_Z 2
#define N_X 3
#define N_Y 4
#define N_Z 5
#define RADIUS 6
#define CONF 7
#define RAD_R 8
#define RAD_G 9
#define RAD_B 10
#define FLOAT_PLANES 11
#define CREATED 0
#define LAST_SEEN 1

#define GATHER16(p, i)                                                                     \
  (p[(i).s0], p[(i).s1], p[(i).s2], p[(i).s3], p[(i).s4], p[(i).s5], p[(i).s6], p[(i).s7], \
   p[(i).s8], p[(i).s9], p[(i).sa], p[(i).sb], p[(i).sc], p[(i).sd], p[(i).se], p[(i).sf])

#define NO_CELL 0xffffffffu
#define EMPTY_CELL 0xffffffffffffffffUL
#define BORN_SATURATED 1
#define BORN_BLACK 2
#define CODE_NONE 0
#define CODE_FUSED 1
#define CODE_BORN 2

// surfel_map.cpp's FrameArg, field for field.
typedef struct {
  float r_cw[9], t_cw[3];  // world -> camera (row-major)
  float r_wc[9], t_wc[3];  // camera -> world
  float fx, fy, cx, cy, f_mean;
  float inv_max_radius_factor, region_r2;
  float region[3];
  float depth_tolerance, cos_normal, violation_margin, discontinuity;
  float min_depth, max_depth, clipped_scale;
  float radiance_per_unit[3];
  int width, height, saturated_level, black_level;
} Frame;

// R v + t with the reference's (Eigen's) order of additions. Scalars only, no float3: PoCL
// leaves a work-item loop with vector-typed values scalar (docs/opencl.md "What PoCL
// vectorises"); with float3 the candidate mask took 1.0 ms a frame on the sim's region.
inline void transform(const float* r, const float* t, float x, float y, float z, float* o) {
  o[0] = ((r[0] * x + r[1] * y) + r[2] * z) + t[0];
  o[1] = ((r[3] * x + r[4] * y) + r[5] * z) + t[1];
  o[2] = ((r[6] * x + r[7] * y) + r[8] * z) + t[2];
}
inline void rotate(const float* r, float x, float y, float z, float* o) {
  o[0] = (r[0] * x + r[1] * y) + r[2] * z;
  o[1] = (r[3] * x + r[4] * y) + r[5] * z;
  o[2] = (r[6] * x + r[7] * y) + r[8] * z;
}
inline float dot3(const float* a, const float* b) {
  return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2];
}
inline void ray(const Frame* f, float x, float y, float z, float* o) {
  o[0] = (x - f->cx) * z / f->fx;
  o[1] = (y - f->cy) * z / f->fy;
  o[2] = z;
}
inline float metres(__global const ushort* depth, int i) {
  return (float)depth[i] * 0.001f;
}

// The index map's cells are cleared where last frame's projection wrote them (`cells`), so a
// frame costs the surfels, not the INDEX_SCALE^2 larger map.
__kernel void clear_index_map(__global ulong* restrict index_map,
                              __global const uint* restrict cells, int n) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const uint c = cells[i];
  if (c != NO_CELL) index_map[c] = EMPTY_CELL;
}

// Every surfel projected into the index map from this frame's pose, the nearest winning and of
// two at one depth the lower index (the reference's strict "<" in index order): atom_min on
// (depth bits << 32 | index), the depth positive so its bits order as the floats do. A surfel
// in front of the nearest depth in the 3 x 3 pixels around it by more than the margin is
// marked for removal (6.2.6) and not entered.
__kernel void project_surfels(__global const float* restrict F, int cap, int n,
                              __global const ushort* restrict depth,
                              __global const float* restrict nearest3, int4 area, const Frame frame,
                              __global ulong* restrict index_map, __global uint* restrict cells,
                              __global uchar* restrict violated) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const Frame* f = &frame;
  float pc[3];
  transform(f->r_cw, f->t_cw, F[P_X * cap + i], F[P_Y * cap + i], F[P_Z * cap + i], pc);
  uint cell = NO_CELL;
  uchar bad = 0;
  const float u = f->fx * pc[0] / pc[2] + f->cx, v = f->fy * pc[1] / pc[2] + f->cy;
  const float cu = floor((u + 0.5f) * (float)INDEX_SCALE);
  const float cv = floor((v + 0.5f) * (float)INDEX_SCALE);
  const int iw = f->width * INDEX_SCALE, ih = f->height * INDEX_SCALE;
  if (pc[2] > 0 && cu >= 0 && cv >= 0 && cu < (float)iw && cv < (float)ih) {
    const int ix = (int)cu, iy = (int)cv;
    const int px = ix / INDEX_SCALE, py = iy / INDEX_SCALE;
    if (depth[py * f->width + px] != 0) {
      float nearest = 0;
      if (px >= area.x && py >= area.y && px < area.z && py < area.w)
        nearest = nearest3[py * f->width + px];  // smooth_depth's, where it ran
      else
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = px + dx, qy = py + dy;
            if (qx < 0 || qy < 0 || qx >= f->width || qy >= f->height) continue;
            const float z = metres(depth, qy * f->width + qx);
            if (z > 0 && (nearest == 0 || z < nearest)) nearest = z;
          }
      bad = pc[2] < nearest - f->violation_margin;
    }
    if (!bad) {
      cell = (uint)iy * (uint)iw + (uint)ix;
      atom_min(&index_map[cell], ((ulong)as_uint(pc[2]) << 32) | (ulong)(uint)i);
    }
  }
  cells[i] = cell;
  violated[i] = bad;
}

// Stores the first `count` lanes of v at p (all 16 when count >= 16: one vector move).
inline void store_lanes_f(__global float* p, vf v, int count) {
  if (count >= VW) {
    STOREF(p, v);
    return;
  }
  float t[VW];
  vstore16(v, 0, t);
  for (int k = 0; k < count; ++k) p[k] = t[k];
}

// Over `outer` (the smoothing's reach around the candidates), 16 pixels of a row a work-item
// (the row-streaming form of vector16.cl: PoCL did not vectorise the per-pixel form across
// work-items, 0.8 CPU-ms a frame on the sim's region): the depth in metres into a copy padded
// by SMOOTH_R zeros on every side, so the smoothing reads its window without bounds tests (a
// zero is skipped as the reference skips a pixel off the image or without depth); and the
// candidate mask, a pixel of `rect` with depth in range whose world point lies in the
// region's sphere (0 elsewhere). Lane for lane the reference's operations.
__kernel void prepare_depth(__global const ushort* restrict depth, const Frame frame, int4 rect,
                            int4 outer, int padded_width, __global float* restrict padded,
                            __global uchar* restrict mask) {
  const int x0 = outer.x + VW * (int)get_global_id(0), y = outer.y + (int)get_global_id(1);
  if (x0 >= outer.z || y >= outer.w) return;
  const Frame* f = &frame;
  const int i = y * f->width + x0, count = outer.z - x0;
  vf z;
  if (count >= VW) {
    z = convert_float16(LOADU16(depth + i)) * 0.001f;
  } else {
    float t[VW];
    for (int k = 0; k < VW; ++k) t[k] = k < count ? (float)depth[i + k] * 0.001f : 0.0f;
    z = vload16(0, t);
  }
  store_lanes_f(padded + (y + PAD) * padded_width + x0 + PAD, z, count);
  const vi xs = x0 + lanes();
  const vf xf = convert_float16(xs);
  const vf pcx = (xf - f->cx) * z / f->fx, pcy = ((float)y - f->cy) * z / f->fy;
  const float* r = f->r_wc;
  const vf dx = (((r[0] * pcx + r[1] * pcy) + r[2] * z) + f->t_wc[0]) - f->region[0];
  const vf dy = (((r[3] * pcx + r[4] * pcy) + r[5] * z) + f->t_wc[1]) - f->region[1];
  const vf dz = (((r[6] * pcx + r[7] * pcy) + r[8] * z) + f->t_wc[2]) - f->region[2];
  const vi in_rect = (xs >= rect.x) & (xs < rect.z) & (vi)(y >= rect.y && y < rect.w ? -1 : 0);
  const vi in_range = ~((z < f->min_depth) | (z > f->max_depth));
  const vi in_region = ~(((dx * dx + dy * dy) + dz * dz) > f->region_r2);
  const uchar16 m = convert_uchar16(in_rect & in_range & in_region & 1);
  if (count >= VW) {
    STOREU8(mask + i, m);
  } else {
    uchar t[VW];
    vstore16(m, 0, t);
    for (int k = 0; k < count; ++k) mask[i + k] = t[k];
  }
}

// Over `area` (the candidates and their normal stencil), 16 pixels a work-item: the depth the
// normals are taken from, the mean over (2 SMOOTH_R + 1)^2 pixels of the depths on the
// centre's side of any silhouette, summed in the reference's order (a skipped pixel adds an
// exact 0); 0 without depth. And the nearest depth around each pixel for the violation test.
__kernel void smooth_depth(__global const float* restrict padded, int padded_width, int width,
                           int4 area, float discontinuity, __global float* restrict smoothed,
                           __global float* restrict nearest3) {
  const int x0 = area.x + VW * (int)get_global_id(0), y = area.y + (int)get_global_id(1);
  if (x0 >= area.z || y >= area.w) return;
  const int c = (y + PAD) * padded_width + x0 + PAD;
  const vf z = LOADF(padded + c);
  const vf jump = discontinuity * z;
  vf sum = 0.0f;
  vi n = 0;
  for (int dy = -SMOOTH_R; dy <= SMOOTH_R; ++dy)
    for (int dx = -SMOOTH_R; dx <= SMOOTH_R; ++dx) {
      const vf zn = LOADF(padded + c + dy * padded_width + dx);
      const vi ok = (zn != 0.0f) & (fabs(zn - z) <= jump);
      sum += select((vf)(0.0f), zn, ok);
      n -= ok;  // a true lane is -1
    }
  const vf out = select((vf)(0.0f), sum / convert_float16(n), z != 0.0f);
  store_lanes_f(smoothed + y * width + x0, out, area.z - x0);
  // The violation test's nearest depth in the 3 x 3 pixels (0 if none), for project_surfels.
  vf nearest = 0.0f;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const vf zn = LOADF(padded + c + dy * padded_width + dx);
      nearest = select(nearest, zn, (zn > 0.0f) & ((nearest == 0.0f) | (zn < nearest)));
    }
  store_lanes_f(nearest3 + y * width + x0, nearest, area.z - x0);
}

// One candidate pixel's observation (6.2.2): world position and normal, radius, radiance,
// weights and flags; false where the stencil crosses a silhouette or gives no normal. The
// fuse and the birth kernels both call it, so a born surfel is what the fuse pass saw.
typedef struct {
  float pw[3], nw[3];
  float z, radius, weight, colour_weight;
  float radiance[3];
  uchar flags;
} Observation;

inline bool observe(const Frame* f, int x, int y, __global const ushort* depth,
                    __global const uchar* colour, __global const float* smoothed,
                    __global const float* radial_weight, __constant float* linear, Observation* o) {
  const int w = f->width, i = y * w + x;
  const float z = metres(depth, i);
  const float zs = smoothed[i], zl = smoothed[i - NORMAL_STEP], zr = smoothed[i + NORMAL_STEP];
  const float zu = smoothed[i - NORMAL_STEP * w], zd = smoothed[i + NORMAL_STEP * w];
  const float jump = f->discontinuity * zs;
  if (zs == 0 || fabs(zl - zs) > jump || fabs(zr - zs) > jump || fabs(zu - zs) > jump ||
      fabs(zd - zs) > jump)
    return false;
  const float fx = (float)x, fy = (float)y, fs = (float)NORMAL_STEP;
  float r0[3], r1[3], u0[3], u1[3];
  ray(f, fx + fs, fy, zr, r1);
  ray(f, fx - fs, fy, zl, r0);
  ray(f, fx, fy + fs, zd, u1);
  ray(f, fx, fy - fs, zu, u0);
  const float a[3] = {r1[0] - r0[0], r1[1] - r0[1], r1[2] - r0[2]};
  const float b[3] = {u1[0] - u0[0], u1[1] - u0[1], u1[2] - u0[2]};
  float n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  const float n_len = sqrt(dot3(n, n));
  if (!(n_len > 0)) return false;
  for (int k = 0; k < 3; ++k) n[k] = n[k] / n_len;
  float pc[3];
  ray(f, fx, fy, z, pc);
  if (dot3(n, pc) > 0)  // towards the camera
    for (int k = 0; k < 3; ++k) n[k] = -n[k];

  const uchar r = colour[3 * i], g = colour[3 * i + 1], bl = colour[3 * i + 2];
  uchar flags = 0;
  if (r >= f->saturated_level || g >= f->saturated_level || bl >= f->saturated_level)
    flags = BORN_SATURATED;
  else if (r < f->black_level && g < f->black_level && bl < f->black_level)
    flags = BORN_BLACK;
  o->radiance[0] = linear[r] * f->radiance_per_unit[0];
  o->radiance[1] = linear[g] * f->radiance_per_unit[1];
  o->radiance[2] = linear[bl] * f->radiance_per_unit[2];
  o->flags = flags;
  o->weight = radial_weight[i];
  o->colour_weight = flags ? o->weight * f->clipped_scale : o->weight;
  o->radius = 1.41421356f * z / f->f_mean / fmax(fabs(n[2]), f->inv_max_radius_factor);
  o->z = z;
  transform(f->r_wc, f->t_wc, pc[0], pc[1], pc[2], o->pw);
  rotate(f->r_wc, n[0], n[1], n[2], o->nw);
  return true;
}

// Per 16 pixels of a row of `rect` (mask set): the observations (lane for lane observe()'s
// operations), the correspondence among the surfels in each pixel's INDEX_SCALE^2 cells and
// the confidence-weighted fuse (6.2.2), all in float16 with gathers. One work-item per pixel
// ran scalar: 24 CPU-ms at VGA (every pixel a candidate), ~13 with the observation
// vectorised, ~11 now; loading the cells as contiguous rows and testing normals lane by lane
// instead was slower (docs/fusion.md "The surfel map on the device"). `codes` says what
// each pixel did: nothing, fused or to be born (births are written in row-major order by
// write_births, which calls observe() for the same values). Loads run up to 15 pixels past the
// rectangle: `rect` ends NORMAL_STEP rows above the image's end.
__kernel void fuse_pixels(__global const ushort* restrict depth,
                          __global const uchar* restrict colour,
                          __global const float* restrict smoothed,
                          __global const float* restrict radial_weight, __constant float* linear,
                          __global const uchar* restrict mask,
                          __global const ulong* restrict index_map, const Frame frame, int4 rect,
                          long frame_index, __global float* restrict F, __global long* restrict T,
                          int cap, __global uchar* restrict codes) {
  const int x0 = rect.x + VW * (int)get_global_id(0), y = rect.y + (int)get_global_id(1);
  if (x0 >= rect.z || y >= rect.w) return;
  const Frame* f = &frame;
  const int w = f->width, i = y * w + x0, count = min(VW, rect.z - x0);
  const vi lane = lanes();
  vi ok = (lane < count) & (convert_int16(LOADU8(mask + i)) != 0);
  uchar out[VW];
  for (int k = 0; k < VW; ++k) out[k] = CODE_NONE;
  if (any(ok)) {
    const vf z = convert_float16(LOADU16(depth + i)) * 0.001f;
    const vf zs = LOADF(smoothed + i), zl = LOADF(smoothed + i - NORMAL_STEP);
    const vf zr = LOADF(smoothed + i + NORMAL_STEP);
    const vf zu = LOADF(smoothed + i - NORMAL_STEP * w), zd = LOADF(smoothed + i + NORMAL_STEP * w);
    const vf jump = f->discontinuity * zs;
    ok &= (zs != 0.0f) & ~(fabs(zl - zs) > jump) & ~(fabs(zr - zs) > jump) &
          ~(fabs(zu - zs) > jump) & ~(fabs(zd - zs) > jump);
    const vf xf = convert_float16(x0 + lane);
    const float yf = (float)y, fs = (float)NORMAL_STEP;
    const float ym = yf - f->cy, yu = (yf + fs) - f->cy, yd = (yf - fs) - f->cy;
    // The stencil's rays, as ray(): ((x - cx) * z) / fx, ((y - cy) * z) / fy.
    const vf r1x = ((xf + fs) - f->cx) * zr / f->fx, r1y = ym * zr / f->fy;
    const vf r0x = ((xf - fs) - f->cx) * zl / f->fx, r0y = ym * zl / f->fy;
    const vf u1x = (xf - f->cx) * zd / f->fx, u1y = yu * zd / f->fy;
    const vf u0x = (xf - f->cx) * zu / f->fx, u0y = yd * zu / f->fy;
    const vf ax = r1x - r0x, ay = r1y - r0y, az = zr - zl;
    const vf bx = u1x - u0x, by = u1y - u0y, bz = zd - zu;
    vf nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
    const vf n_len = sqrt((nx * nx + ny * ny) + nz * nz);
    ok &= n_len > 0.0f;
    nx = nx / n_len, ny = ny / n_len, nz = nz / n_len;
    const vf pcx = (xf - f->cx) * z / f->fx, pcy = ym * z / f->fy;
    const vi flip = ((nx * pcx + ny * pcy) + nz * z) > 0.0f;  // towards the camera
    nx = select(nx, -nx, flip), ny = select(ny, -ny, flip), nz = select(nz, -nz, flip);
    vf rf, gf, bf;
    load_rgb16(colour + 3 * i, &rf, &gf, &bf);
    const vi R = convert_int16(rf), G = convert_int16(gf), B = convert_int16(bf);
    const vi sat =
        (R >= f->saturated_level) | (G >= f->saturated_level) | (B >= f->saturated_level);
    const vi black = ~sat & (R < f->black_level) & (G < f->black_level) & (B < f->black_level);
    const vi flags = select(select((vi)(0), (vi)(BORN_BLACK), black), (vi)(BORN_SATURATED), sat);
    const vf weight = LOADF(radial_weight + i);
    const vf colour_weight = select(weight, weight * f->clipped_scale, flags != 0);
    const vf radius = 1.41421356f * z / f->f_mean / fmax(fabs(nz), f->inv_max_radius_factor);
    const float* r = f->r_wc;
    const float* t = f->t_wc;
    const vf pw[3] = {((r[0] * pcx + r[1] * pcy) + r[2] * z) + t[0],
                      ((r[3] * pcx + r[4] * pcy) + r[5] * z) + t[1],
                      ((r[6] * pcx + r[7] * pcy) + r[8] * z) + t[2]};
    const vf nw[3] = {(r[0] * nx + r[1] * ny) + r[2] * nz, (r[3] * nx + r[4] * ny) + r[5] * nz,
                      (r[6] * nx + r[7] * ny) + r[8] * nz};
    // The correspondence, the 16 pixels at once, cell by cell in the reference's row-major
    // order (a lane takes a cell only where the reference would: not empty, nearer than its
    // best so far, the normal within the tolerance). Lanes that take nothing read cell / surfel 0.
    const int iw = w * INDEX_SCALE;
    vi best = -1;
    vf best_dz = f->depth_tolerance;
    for (int cy = 0; cy < INDEX_SCALE; ++cy)
      for (int cx = 0; cx < INDEX_SCALE; ++cx) {
        const vi ci =
            select((vi)(0), (y * INDEX_SCALE + cy) * iw + (x0 + lane) * INDEX_SCALE + cx, ok);
        const ulong16 cell = (ulong16)GATHER16(index_map, ci);
        const vi full = convert_int16(cell != EMPTY_CELL);
        const vi id = as_int16(convert_uint16(cell & 0xffffffffUL));
        const vf dz = fabs(as_float16(convert_uint16(cell >> 32)) - z);
        const vi near = ok & full & ~(dz >= best_dz);
        if (!any(near)) continue;
        const vi idm = select((vi)(0), id, near);
        const vf snx = (vf)GATHER16((F + N_X * cap), idm), sny = (vf)GATHER16((F + N_Y * cap), idm);
        const vf snz = (vf)GATHER16((F + N_Z * cap), idm);
        const vi take = near & ~(((snx * nw[0] + sny * nw[1]) + snz * nw[2]) < f->cos_normal);
        best = select(best, id, take);
        best_dz = select(best_dz, dz, take);
      }
    // The fuse (the reference's arithmetic), gathered and written back per matched lane: a surfel
    // is in one pixel's cells only, so no two lanes or work-items write one surfel.
    const vi matched = ok & (best >= 0);
    if (any(matched)) {
      const vi b = select((vi)(0), best, matched);
      const vf c = (vf)GATHER16((F + CONF * cap), b);
      const vf sum = c + weight, colour_sum = c + colour_weight;
      float a_out[FLOAT_PLANES][VW];
      vf nn[3];
      for (int k = 0; k < 3; ++k) {
        const vf p = (vf)GATHER16((F + (P_X + k) * cap), b);
        vstore16((c * p + weight * pw[k]) / sum, 0, a_out[P_X + k]);
        nn[k] = c * (vf)GATHER16((F + (N_X + k) * cap), b) + weight * nw[k];
      }
      const vf nn2 = (nn[0] * nn[0] + nn[1] * nn[1]) + nn[2] * nn[2];
      const vi nonzero = nn2 > 0.0f;
      for (int k = 0; k < 3; ++k)  // Eigen's normalized()
        vstore16(select(nn[k], nn[k] / sqrt(nn2), nonzero), 0, a_out[N_X + k]);
      vstore16((c * (vf)GATHER16((F + RADIUS * cap), b) + weight * radius) / sum, 0, a_out[RADIUS]);
      const vi channel[3] = {R, G, B};
      for (int k = 0; k < 3; ++k) {
        const vf radiance = (vf)GATHER16(linear, channel[k]) * f->radiance_per_unit[k];
        const vf old = (vf)GATHER16((F + (RAD_R + k) * cap), b);
        vstore16((c * old + colour_weight * radiance) / colour_sum, 0, a_out[RAD_R + k]);
      }
      vstore16(sum, 0, a_out[CONF]);
      int a_best[VW], a_matched[VW];
      vstore16(b, 0, a_best);
      vstore16(matched, 0, a_matched);
      for (int k = 0; k < count; ++k) {
        if (!a_matched[k]) continue;
        for (int q = 0; q < FLOAT_PLANES; ++q) F[q * cap + a_best[k]] = a_out[q][k];
        T[LAST_SEEN * cap + a_best[k]] = frame_index;
      }
    }
    int a_code[VW];
    vstore16(select(select((vi)(CODE_NONE), (vi)(CODE_BORN), ok), (vi)(CODE_FUSED), matched), 0,
             a_code);
    for (int k = 0; k < count; ++k) out[k] = (uchar)a_code[k];
  }
  for (int k = 0; k < count; ++k) codes[i + k] = out[k];
}

// Per row of `rect`: how many of its pixels fused and how many are to be born.
__kernel void count_row_codes(__global const uchar* restrict codes, int width, int4 rect,
                              __global uint* restrict fused_rows,
                              __global uint* restrict born_rows) {
  const int r = get_global_id(0);
  const int y = rect.y + r;
  if (y >= rect.w) return;
  uint fused = 0, born = 0;
  for (int x = rect.x; x < rect.z; ++x) {
    const uchar c = codes[y * width + x];
    fused += c == CODE_FUSED;
    born += c == CODE_BORN;
  }
  fused_rows[r] = fused;
  born_rows[r] = born;
}

// Per block of BLOCK surfels: which stay (neither violated nor unstable and unseen for more
// than max_unseen frames, 6.2.2 / 6.2.6), and the block's counts.
__kernel void keep_frame_rule(__global const float* restrict F, __global const long* restrict T,
                              int cap, int n, __global const uchar* restrict violated,
                              float stable_confidence, long max_unseen, long frame_index,
                              __global uchar* restrict keep, __global uint* restrict block_kept,
                              __global uint* restrict block_violated,
                              __global uint* restrict block_stale) {
  const int b = get_global_id(0);
  const int i0 = b * BLOCK;
  if (i0 >= n) return;
  const int i1 = min(i0 + BLOCK, n);
  uint kept = 0, bad = 0, stale = 0;
  for (int i = i0; i < i1; ++i) {
    const bool v = violated[i];
    const bool s = !v && !(F[CONF * cap + i] >= stable_confidence) &&
                   frame_index - T[LAST_SEEN * cap + i] > max_unseen;
    keep[i] = !v && !s;
    kept += !v && !s;
    bad += v;
    stale += s;
  }
  block_kept[b] = kept;
  block_violated[b] = bad;
  block_stale[b] = stale;
}

// One work-item: the exclusive scans of the blocks' kept counts and of the rows' births (which
// follow the kept surfels), and the frame's totals: kept, born, fused, violated, stale.
__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void scan_counts(
    __global uint* restrict block_kept, __global const uint* restrict block_violated,
    __global const uint* restrict block_stale, int blocks, __global const uint* restrict fused_rows,
    __global uint* restrict born_rows, int rows, __global uint* restrict totals) {
  uint kept = 0, bad = 0, stale = 0;
  for (int b = 0; b < blocks; ++b) {
    const uint k = block_kept[b];
    block_kept[b] = kept;
    kept += k;
    bad += block_violated[b];
    stale += block_stale[b];
  }
  uint born = 0, fused = 0;
  for (int r = 0; r < rows; ++r) {
    const uint k = born_rows[r];
    born_rows[r] = kept + born;
    born += k;
    fused += fused_rows[r];
  }
  totals[0] = kept;
  totals[1] = born;
  totals[2] = fused;
  totals[3] = bad;
  totals[4] = stale;
}

// Per block: its kept surfels to the other set, in order, from the block's offset.
__kernel void compact_surfels(__global const float* restrict F, __global const long* restrict T,
                              __global const uchar* restrict FL, int cap, int n,
                              __global const uchar* restrict keep,
                              __global const uint* restrict block_offset,
                              __global float* restrict F2, __global long* restrict T2,
                              __global uchar* restrict FL2, int cap2) {
  const int b = get_global_id(0);
  const int i0 = b * BLOCK;
  if (i0 >= n) return;
  const int i1 = min(i0 + BLOCK, n);
  uint o = block_offset[b];
  for (int i = i0; i < i1; ++i) {
    if (!keep[i]) continue;
    for (int k = 0; k < FLOAT_PLANES; ++k) F2[k * cap2 + o] = F[k * cap + i];
    T2[CREATED * cap2 + o] = T[CREATED * cap + i];
    T2[LAST_SEEN * cap2 + o] = T[LAST_SEEN * cap + i];
    FL2[o] = FL[i];
    ++o;
  }
}

// Per row of `rect`: its births, new unstable surfels (clipped pixels start lower, 6.2.2),
// written in row-major order after the kept surfels: the reference's order.
__kernel void write_births(__global const ushort* restrict depth,
                           __global const uchar* restrict colour,
                           __global const float* restrict smoothed,
                           __global const float* restrict radial_weight, __constant float* linear,
                           __global const uchar* restrict codes, const Frame frame, int4 rect,
                           __global const uint* restrict row_offset, long frame_index,
                           __global float* restrict F, __global long* restrict T,
                           __global uchar* restrict FL, int cap) {
  const int r = get_global_id(0);
  const int y = rect.y + r;
  if (y >= rect.w) return;
  const Frame* f = &frame;
  uint o = row_offset[r];
  for (int x = rect.x; x < rect.z; ++x) {
    if (codes[y * f->width + x] != CODE_BORN) continue;
    Observation ob;
    observe(f, x, y, depth, colour, smoothed, radial_weight, linear, &ob);  // true: it was born
    for (int k = 0; k < 3; ++k) {
      F[(P_X + k) * cap + o] = ob.pw[k];
      F[(N_X + k) * cap + o] = ob.nw[k];
    }
    F[RADIUS * cap + o] = ob.radius;
    F[CONF * cap + o] = ob.colour_weight;
    F[RAD_R * cap + o] = ob.radiance[0];
    F[RAD_G * cap + o] = ob.radiance[1];
    F[RAD_B * cap + o] = ob.radiance[2];
    T[CREATED * cap + o] = frame_index;
    T[LAST_SEEN * cap + o] = frame_index;
    FL[o] = ob.flags;
    ++o;
  }
}

// The budget's eviction order (issue #21 item 1; the reference's): farthest shell first, then
// the least confident, then the newest (highest index). As a key that is larger for what goes
// first: (shell, ~confidence bits, index), the shell clamped to 16 bits (3.3 km at 5 cm).
inline uint3 eviction_key(__global const float* F, int cap, int i, float4 centre, float shell_m) {
  const float d[3] = {F[P_X * cap + i] - centre.x, F[P_Y * cap + i] - centre.y,
                      F[P_Z * cap + i] - centre.z};
  const float shell = floor(sqrt(dot3(d, d)) / shell_m);
  return (uint3)((uint)min(shell, 65535.0f), ~as_uint(F[CONF * cap + i]), (uint)i);
}

// The radix select of the `excess`-th largest key, 8 bits a pass from the top (2 passes of the
// shell, 4 of the confidence, 3 of the index): state = {need, prefix[3], mask[3]}.
inline bool matches(uint3 key, __global const uint* state) {
  return (key.x & state[4]) == state[1] && (key.y & state[5]) == state[2] &&
         (key.z & state[6]) == state[3];
}
inline uint key_word(uint3 key, int word) {
  return word == 0 ? key.x : word == 1 ? key.y : key.z;
}

__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void eviction_histogram(
    __global const float* restrict F, int cap, int n, float4 centre, float shell_m,
    __global const uint* restrict state, int word, int shift, int chunk,
    __global uint* restrict histogram) {
  const int i0 = get_global_id(0) * chunk;
  if (i0 >= n) return;
  const int i1 = min(i0 + chunk, n);
  uint local_hist[256];
  for (int d = 0; d < 256; ++d) local_hist[d] = 0;
  for (int i = i0; i < i1; ++i) {
    const uint3 key = eviction_key(F, cap, i, centre, shell_m);
    if (matches(key, state)) ++local_hist[(key_word(key, word) >> shift) & 0xffu];
  }
  for (int d = 0; d < 256; ++d)
    if (local_hist[d]) atomic_add(&histogram[d], local_hist[d]);
}

__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void eviction_select(
    __global uint* restrict histogram, __global uint* restrict state, int word, int shift) {
  const uint need = state[0];
  uint above = 0;
  int digit = 0;
  for (int d = 255; d >= 0; --d) {
    if (above + histogram[d] >= need) {
      digit = d;
      break;
    }
    above += histogram[d];
  }
  state[0] = need - above;
  state[1 + word] |= (uint)digit << shift;
  state[4 + word] |= 0xffu << shift;
  for (int d = 0; d < 256; ++d) histogram[d] = 0;
}

// Per block: the surfels below the selected key stay (keys are unique: exactly `excess` go).
__kernel void keep_below_key(__global const float* restrict F, int cap, int n, float4 centre,
                             float shell_m, __global const uint* restrict state,
                             __global uchar* restrict keep, __global uint* restrict block_kept) {
  const int b = get_global_id(0);
  const int i0 = b * BLOCK;
  if (i0 >= n) return;
  const int i1 = min(i0 + BLOCK, n);
  const uint3 t = (uint3)(state[1], state[2], state[3]);
  uint kept = 0;
  for (int i = i0; i < i1; ++i) {
    const uint3 k = eviction_key(F, cap, i, centre, shell_m);
    const bool stays = k.x < t.x || (k.x == t.x && (k.y < t.y || (k.y == t.y && k.z < t.z)));
    keep[i] = stays;
    kept += stays;
  }
  block_kept[b] = kept;
}
