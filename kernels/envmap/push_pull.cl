// Push-pull inpainting of a keyframe's unobserved texels, per cube face (S. J. Gortler et al.,
// "The Lumigraph", SIGGRAPH 1996, sec. 3.4.2; docs/light-capture.md). Images are stacks of six
// m x m faces (row = face * m + y) of float4; on the keyframe itself (level 0) a texel's weight
// is 1 when its alpha is non-zero (observed, or < 0: seeded from a neighbour face this call),
// else 0; on coarser levels alpha is the weight. face_mask: bit f set = work on face f.
// push_pull_reference.cpp mirrors every step.

float level_weight(float4 t, int is_texels) {
  return is_texels ? (t.w != 0.0f ? 1.0f : 0.0f) : t.w;
}

// Pull: a coarse texel is the weighted mean of its (up to) 2 x 2 children, weight min(1, sum).
__kernel void pull(__global const float4* fine, int fine_size, int fine_is_texels,
                   __global float4* coarse, int coarse_size, int face_mask) {
  const int x = get_global_id(0), row = get_global_id(1);
  if (x >= coarse_size || row >= 6 * coarse_size) return;
  const int face = row / coarse_size, y = row - face * coarse_size;
  if (!((face_mask >> face) & 1)) return;
  float3 sum = (float3)(0.0f);
  float wsum = 0.0f;
  for (int j = 0; j < 2; ++j) {
    const int fy = 2 * y + j;
    if (fy >= fine_size) break;
    for (int i = 0; i < 2; ++i) {
      const int fx = 2 * x + i;
      if (fx >= fine_size) break;
      const float4 t = fine[(face * fine_size + fy) * fine_size + fx];
      const float w = level_weight(t, fine_is_texels);
      sum += w * t.xyz;
      wsum += w;
    }
  }
  coarse[row * coarse_size + x] =
      wsum > 0.0f ? (float4)(sum / wsum, fmin(wsum, 1.0f)) : (float4)(0.0f);
}

// Push: a fine texel of weight w < 1 becomes w itself + (1 - w) its parent. On the keyframe
// that leaves observed texels bit for bit, fills unobserved ones with the parent, and turns
// this call's seeded borders (alpha < 0) back into unobserved (alpha 0) texels.
__kernel void push(__global float4* fine, int fine_size, int fine_is_texels,
                   __global const float4* coarse, int coarse_size, int face_mask) {
  const int x = get_global_id(0), row = get_global_id(1);
  if (x >= fine_size || row >= 6 * fine_size) return;
  const int face = row / fine_size, y = row - face * fine_size;
  if (!((face_mask >> face) & 1)) return;
  const int i = row * fine_size + x;
  const float4 t = fine[i];
  const float4 parent = coarse[(face * coarse_size + y / 2) * coarse_size + x / 2];
  if (fine_is_texels) {
    if (t.w == 0.0f) fine[i] = (float4)(parent.xyz, 0.0f);
    else if (t.w < 0.0f) fine[i] = (float4)(t.xyz, 0.0f);
  } else if (t.w < 1.0f) {
    fine[i] = (float4)(t.w * t.xyz + (1.0f - t.w) * parent.xyz, 1.0f);
  }
}

// --- Across face edges ---

float3 cube_direction(int face, float u, float v) {
  const float sc = 2.0f * u - 1.0f, tc = 2.0f * v - 1.0f;
  switch (face) {
    case 0: return (float3)(1.0f, -tc, -sc);
    case 1: return (float3)(-1.0f, -tc, sc);
    case 2: return (float3)(sc, 1.0f, tc);
    case 3: return (float3)(sc, -1.0f, -tc);
    case 4: return (float3)(sc, -tc, 1.0f);
    default: return (float3)(-sc, -tc, -1.0f);
  }
}

// Direction -> face and texel (core/cubemap.cpp's cube_texel_from_direction).
int cube_texel(float3 d, int n, int* tx, int* ty) {
  const float ax = fabs(d.x), ay = fabs(d.y), az = fabs(d.z);
  int face;
  float sc, tc, ma;
  if (ax >= ay && ax >= az) {
    ma = ax;
    if (d.x > 0.0f) { face = 0; sc = -d.z; tc = -d.y; }
    else { face = 1; sc = d.z; tc = -d.y; }
  } else if (ay >= az) {
    ma = ay;
    if (d.y > 0.0f) { face = 2; sc = d.x; tc = d.z; }
    else { face = 3; sc = d.x; tc = -d.z; }
  } else {
    ma = az;
    if (d.z > 0.0f) { face = 4; sc = d.x; tc = -d.y; }
    else { face = 5; sc = -d.x; tc = -d.y; }
  }
  const float u = 0.5f * (sc / ma + 1.0f), v = 0.5f * (tc / ma + 1.0f);
  *tx = clamp((int)(u * (float)n), 0, n - 1);
  *ty = clamp((int)(v * (float)n), 0, n - 1);
  return face;
}

// Seeds the border texels of the faces in empty_mask from the edge texels of the adjacent
// faces in source_mask: the texel one step outside the face's edge, looked up by direction,
// marked alpha = -1. Work-items: (i, face * 4 + edge); edges 0/1 are the top/bottom rows
// (corners included), 2/3 the left/right columns without the corners (one writer per texel).
__kernel void seed_borders(__global float4* texels, int n, int empty_mask, int source_mask) {
  const int i = get_global_id(0), fe = get_global_id(1);
  if (i >= n || fe >= 24) return;
  const int face = fe / 4, edge = fe - 4 * face;
  if (!((empty_mask >> face) & 1)) return;
  int x, y;
  float du = 0.0f, dv = 0.0f;
  if (edge < 2) {
    x = i;
    y = edge == 0 ? 0 : n - 1;
    dv = edge == 0 ? -1.0f : 1.0f;
  } else {
    if (i == 0 || i == n - 1) return;
    y = i;
    x = edge == 2 ? 0 : n - 1;
    du = edge == 2 ? -1.0f : 1.0f;
  }
  const float inv_n = 1.0f / (float)n;
  const float3 d =
      cube_direction(face, ((float)x + 0.5f + du) * inv_n, ((float)y + 0.5f + dv) * inv_n);
  int sx, sy;
  const int source = cube_texel(d, n, &sx, &sy);
  if (source == face || !((source_mask >> source) & 1)) return;
  const float4 s = texels[(source * n + sy) * n + sx];
  texels[(face * n + y) * n + x] = (float4)(s.xyz, -1.0f);
}
