// The HDR surfel map on the device (surfel_map.hpp, docs/fusion.md "The surfel map on the
// device"); surfel_map_reference.cpp is the specification, rule for rule and operation for
// operation, so that the device takes the reference's decisions (contraction into fma off; the
// radial weights and the 8-bit linearisation come from the host's std:: functions as tables).
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

#if !defined(INDEX_SCALE) || !defined(NORMAL_STEP) || !defined(SMOOTH_R) || !defined(BLOCK)
#error "surfel_map.cl needs -DINDEX_SCALE, -DNORMAL_STEP, -DSMOOTH_R and -DBLOCK"
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

// R v + t with the reference's (Eigen's) order of additions.
inline float3 transform(const float* r, const float* t, float3 v) {
  return (float3)(((r[0] * v.x + r[1] * v.y) + r[2] * v.z) + t[0],
                  ((r[3] * v.x + r[4] * v.y) + r[5] * v.z) + t[1],
                  ((r[6] * v.x + r[7] * v.y) + r[8] * v.z) + t[2]);
}
inline float3 rotate(const float* r, float3 v) {
  return (float3)((r[0] * v.x + r[1] * v.y) + r[2] * v.z, (r[3] * v.x + r[4] * v.y) + r[5] * v.z,
                  (r[6] * v.x + r[7] * v.y) + r[8] * v.z);
}
inline float dot3(float3 a, float3 b) {
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
inline float3 ray(const Frame* f, float x, float y, float z) {
  return (float3)((x - f->cx) * z / f->fx, (y - f->cy) * z / f->fy, z);
}
inline float metres(__global const ushort* depth, int i) {
  return (float)depth[i] * 0.001f;
}

// The index map's cells are cleared where last frame's projection wrote them (`cells`), so a
// frame costs the surfels, not the INDEX_SCALE^2 larger map.
__kernel void clear_index_map(__global ulong* index_map, __global const uint* cells, int n) {
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
__kernel void project_surfels(__global const float* F, int cap, int n, __global const ushort* depth,
                              const Frame frame, __global ulong* index_map, __global uint* cells,
                              __global uchar* violated) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const Frame* f = &frame;
  cells[i] = NO_CELL;
  violated[i] = 0;
  const float3 pc =
      transform(f->r_cw, f->t_cw, (float3)(F[P_X * cap + i], F[P_Y * cap + i], F[P_Z * cap + i]));
  if (pc.z <= 0) return;
  const float u = f->fx * pc.x / pc.z + f->cx, v = f->fy * pc.y / pc.z + f->cy;
  const float cu = floor((u + 0.5f) * (float)INDEX_SCALE);
  const float cv = floor((v + 0.5f) * (float)INDEX_SCALE);
  const int iw = f->width * INDEX_SCALE, ih = f->height * INDEX_SCALE;
  if (cu < 0 || cv < 0 || cu >= (float)iw || cv >= (float)ih) return;
  const int ix = (int)cu, iy = (int)cv;
  const int px = ix / INDEX_SCALE, py = iy / INDEX_SCALE;
  if (depth[py * f->width + px] != 0) {
    float nearest = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int qx = px + dx, qy = py + dy;
        if (qx < 0 || qy < 0 || qx >= f->width || qy >= f->height) continue;
        const float z = metres(depth, qy * f->width + qx);
        if (z > 0 && (nearest == 0 || z < nearest)) nearest = z;
      }
    if (pc.z < nearest - f->violation_margin) {
      violated[i] = 1;
      return;
    }
  }
  const uint cell = (uint)iy * (uint)iw + (uint)ix;
  cells[i] = cell;
  atom_min(&index_map[cell], ((ulong)as_uint(pc.z) << 32) | (ulong)(uint)i);
}

// Which pixels of `rect` (the region's projection within the normal stencil's border) are
// candidates: depth in range and the world point in the region's sphere. Written over
// `area`, which holds `rect`, 0 outside `rect`, so the smoothing may read it anywhere there.
__kernel void region_mask(__global const ushort* depth, const Frame frame, int4 rect, int4 area,
                          __global uchar* mask) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= area.z || y >= area.w) return;
  const Frame* f = &frame;
  const int i = y * f->width + x;
  uchar in = 0;
  if (x >= rect.x && y >= rect.y && x < rect.z && y < rect.w) {
    const float z = metres(depth, i);
    if (!(z < f->min_depth || z > f->max_depth)) {
      const float3 pw = transform(f->r_wc, f->t_wc, ray(f, (float)x, (float)y, z));
      const float3 d = pw - (float3)(f->region[0], f->region[1], f->region[2]);
      in = !(dot3(d, d) > f->region_r2);
    }
  }
  mask[i] = in;
}

inline uchar masked(__global const uchar* mask, int4 area, int width, int x, int y) {
  return x >= area.x && y >= area.y && x < area.z && y < area.w ? mask[y * width + x] : 0;
}

// The depth the normals are taken from, where a candidate's stencil needs it: the mean over
// (2 SMOOTH_R + 1)^2 pixels of the depths on the centre's side of any silhouette, summed in
// the reference's order; 0 without depth.
__kernel void smooth_depth(__global const ushort* depth, __global const uchar* mask, int4 area,
                           int width, int height, float discontinuity, __global float* smoothed) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= area.z || y >= area.w) return;
  if (!(masked(mask, area, width, x, y) | masked(mask, area, width, x - NORMAL_STEP, y) |
        masked(mask, area, width, x + NORMAL_STEP, y) |
        masked(mask, area, width, x, y - NORMAL_STEP) |
        masked(mask, area, width, x, y + NORMAL_STEP)))
    return;
  const int i = y * width + x;
  const float z = metres(depth, i);
  float out = 0;
  if (z != 0) {
    const float jump = discontinuity * z;
    float sum = 0;
    int n = 0;
    for (int dy = max(-SMOOTH_R, -y); dy <= min(SMOOTH_R, height - 1 - y); ++dy)
      for (int dx = max(-SMOOTH_R, -x); dx <= min(SMOOTH_R, width - 1 - x); ++dx) {
        const float zn = metres(depth, i + dy * width + dx);
        if (zn != 0 && fabs(zn - z) <= jump) {
          sum += zn;
          ++n;
        }
      }
    out = sum / (float)n;
  }
  smoothed[i] = out;
}

// One candidate pixel's observation (6.2.2): world position and normal, radius, radiance,
// weights and flags; false where the stencil crosses a silhouette or gives no normal. The
// fuse and the birth kernels both call it, so a born surfel is what the fuse pass saw.
typedef struct {
  float3 pw, nw;
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
  const float3 a = ray(f, fx + fs, fy, zr) - ray(f, fx - fs, fy, zl);
  const float3 b = ray(f, fx, fy + fs, zd) - ray(f, fx, fy - fs, zu);
  float3 n = (float3)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  const float n_len = sqrt(dot3(n, n));
  if (!(n_len > 0)) return false;
  n = n / n_len;
  const float3 pc = ray(f, fx, fy, z);
  if (dot3(n, pc) > 0) n = -n;  // towards the camera

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
  o->radius = 1.41421356f * z / f->f_mean / fmax(fabs(n.z), f->inv_max_radius_factor);
  o->z = z;
  o->pw = transform(f->r_wc, f->t_wc, pc);
  o->nw = rotate(f->r_wc, n);
  return true;
}

// Per pixel of `rect` (mask set): the observation, its correspondence among the surfels in
// its INDEX_SCALE^2 cells (the closest depth within the tolerance whose normal agrees, the
// first in row-major order on a tie), and the confidence-weighted fuse (6.2.2). `codes` says
// what the pixel did: nothing, fused or to be born (births are written in row-major order by
// write_births).
__kernel void fuse_pixels(__global const ushort* depth, __global const uchar* colour,
                          __global const float* smoothed, __global const float* radial_weight,
                          __constant float* linear, __global const uchar* mask,
                          __global const ulong* index_map, const Frame frame, int4 rect,
                          long frame_index, __global float* F, __global long* T, int cap,
                          __global uchar* codes) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= rect.z || y >= rect.w) return;
  const Frame* f = &frame;
  const int i = y * f->width + x;
  uchar code = CODE_NONE;
  Observation o;
  if (mask[i] && observe(f, x, y, depth, colour, smoothed, radial_weight, linear, &o)) {
    const int iw = f->width * INDEX_SCALE;
    uint best = NO_CELL;
    float best_dz = f->depth_tolerance;
    for (int cy = y * INDEX_SCALE; cy < (y + 1) * INDEX_SCALE; ++cy)
      for (int cx = x * INDEX_SCALE; cx < (x + 1) * INDEX_SCALE; ++cx) {
        const ulong cell = index_map[cy * iw + cx];
        if (cell == EMPTY_CELL) continue;
        const uint id = (uint)cell;
        const float dz = fabs(as_float((uint)(cell >> 32)) - o.z);
        if (dz >= best_dz) continue;
        const float3 sn = (float3)(F[N_X * cap + id], F[N_Y * cap + id], F[N_Z * cap + id]);
        if (dot3(sn, o.nw) < f->cos_normal) continue;
        best = id;
        best_dz = dz;
      }
    if (best != NO_CELL) {
      const float c = F[CONF * cap + best], sum = c + o.weight, colour_sum = c + o.colour_weight;
      const float3 p = (float3)(F[P_X * cap + best], F[P_Y * cap + best], F[P_Z * cap + best]);
      const float3 sn = (float3)(F[N_X * cap + best], F[N_Y * cap + best], F[N_Z * cap + best]);
      const float3 np = (c * p + o.weight * o.pw) / sum;
      float3 nn = c * sn + o.weight * o.nw;
      const float nn2 = dot3(nn, nn);
      if (nn2 > 0) nn = nn / sqrt(nn2);  // Eigen's normalized()
      F[P_X * cap + best] = np.x;
      F[P_Y * cap + best] = np.y;
      F[P_Z * cap + best] = np.z;
      F[N_X * cap + best] = nn.x;
      F[N_Y * cap + best] = nn.y;
      F[N_Z * cap + best] = nn.z;
      F[RADIUS * cap + best] = (c * F[RADIUS * cap + best] + o.weight * o.radius) / sum;
      for (int ch = 0; ch < 3; ++ch) {
        const int k = (RAD_R + ch) * cap + best;
        F[k] = (c * F[k] + o.colour_weight * o.radiance[ch]) / colour_sum;
      }
      F[CONF * cap + best] = sum;
      T[LAST_SEEN * cap + best] = frame_index;
      code = CODE_FUSED;
    } else {
      code = CODE_BORN;
    }
  }
  codes[i] = code;
}

// Per row of `rect`: how many of its pixels fused and how many are to be born.
__kernel void count_row_codes(__global const uchar* codes, int width, int4 rect,
                              __global uint* fused_rows, __global uint* born_rows) {
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
__kernel void keep_frame_rule(__global const float* F, __global const long* T, int cap, int n,
                              __global const uchar* violated, float stable_confidence,
                              long max_unseen, long frame_index, __global uchar* keep,
                              __global uint* block_kept, __global uint* block_violated,
                              __global uint* block_stale) {
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
    __global uint* block_kept, __global const uint* block_violated,
    __global const uint* block_stale, int blocks, __global const uint* fused_rows,
    __global uint* born_rows, int rows, __global uint* totals) {
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
__kernel void compact_surfels(__global const float* F, __global const long* T,
                              __global const uchar* FL, int cap, int n, __global const uchar* keep,
                              __global const uint* block_offset, __global float* F2,
                              __global long* T2, __global uchar* FL2, int cap2) {
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
__kernel void write_births(__global const ushort* depth, __global const uchar* colour,
                           __global const float* smoothed, __global const float* radial_weight,
                           __constant float* linear, __global const uchar* codes, const Frame frame,
                           int4 rect, __global const uint* row_offset, long frame_index,
                           __global float* F, __global long* T, __global uchar* FL, int cap) {
  const int r = get_global_id(0);
  const int y = rect.y + r;
  if (y >= rect.w) return;
  const Frame* f = &frame;
  uint o = row_offset[r];
  for (int x = rect.x; x < rect.z; ++x) {
    if (codes[y * f->width + x] != CODE_BORN) continue;
    Observation ob;
    observe(f, x, y, depth, colour, smoothed, radial_weight, linear, &ob);  // true: it was born
    F[P_X * cap + o] = ob.pw.x;
    F[P_Y * cap + o] = ob.pw.y;
    F[P_Z * cap + o] = ob.pw.z;
    F[N_X * cap + o] = ob.nw.x;
    F[N_Y * cap + o] = ob.nw.y;
    F[N_Z * cap + o] = ob.nw.z;
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
inline uint3 eviction_key(__global const float* F, int cap, int i, float3 centre, float shell_m) {
  const float3 d = (float3)(F[P_X * cap + i], F[P_Y * cap + i], F[P_Z * cap + i]) - centre;
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
    __global const float* F, int cap, int n, float4 centre, float shell_m,
    __global const uint* state, int word, int shift, int chunk, __global uint* histogram) {
  const int i0 = get_global_id(0) * chunk;
  if (i0 >= n) return;
  const int i1 = min(i0 + chunk, n);
  uint local_hist[256];
  for (int d = 0; d < 256; ++d) local_hist[d] = 0;
  for (int i = i0; i < i1; ++i) {
    const uint3 key = eviction_key(F, cap, i, centre.xyz, shell_m);
    if (matches(key, state)) ++local_hist[(key_word(key, word) >> shift) & 0xffu];
  }
  for (int d = 0; d < 256; ++d)
    if (local_hist[d]) atomic_add(&histogram[d], local_hist[d]);
}

__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void eviction_select(
    __global uint* histogram, __global uint* state, int word, int shift) {
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
__kernel void keep_below_key(__global const float* F, int cap, int n, float4 centre, float shell_m,
                             __global const uint* state, __global uchar* keep,
                             __global uint* block_kept) {
  const int b = get_global_id(0);
  const int i0 = b * BLOCK;
  if (i0 >= n) return;
  const int i1 = min(i0 + BLOCK, n);
  const uint3 t = (uint3)(state[1], state[2], state[3]);
  uint kept = 0;
  for (int i = i0; i < i1; ++i) {
    const uint3 k = eviction_key(F, cap, i, centre.xyz, shell_m);
    const bool stays = k.x < t.x || (k.x == t.x && (k.y < t.y || (k.y == t.y && k.z < t.z)));
    keep[i] = stays;
    kept += stays;
  }
  block_kept[b] = kept;
}
