// Push-pull inpainting of a keyframe's unobserved texels, per cube face (S. J. Gortler et al.,
// "The Lumigraph", SIGGRAPH 1996, sec. 3.4.2; docs/light-capture.md). Images are stacks of six
// m x m faces (face-major) of float4; on the keyframe itself (level 0) a texel's weight is 1
// when its alpha is non-zero (observed, or < 0: seeded from a neighbour face this call), else
// 0; on coarser levels alpha is the weight. push_pull_reference.cpp mirrors every step.

float level_weight(float4 t, int is_texels) {
  return is_texels ? (t.w != 0.0f ? 1.0f : 0.0f) : t.w;
}

// The pyramid buffer holds levels 1..: level k (faces of m_k = ceil(m_(k-1) / 2) texels,
// down to 1) starts after 6 m_j^2 texels of every level j < k.
int level_size(int n, int k) {
  int m = n;
  for (int j = 0; j < k; ++j) m = (m + 1) / 2;
  return m;
}

// One work-group per face runs the whole pyramid, pull then push, with barriers between
// levels: 2 launches per pass instead of 2 per level (on PoCL a launch costs about as much as
// a small level's work). face_state[f]: 0 = no data, 2 = observed texels, 1 = filled from
// neighbours; pass 0 works on every face and sets 0 or 2, later passes on the faces
// seed_borders picked (face_target) and set 1.
__kernel void pull_push_faces(__global float4* texels, int n, __global float4* pyramid,
                              __global int* face_state, __global const int* face_target, int pass) {
  const int face = get_group_id(0), lid = get_local_id(0), size = get_local_size(0);
  if (pass > 0 && !face_target[face]) return;  // uniform across the work-group
  int levels = 0;
  for (int m = n; m > 1; m = (m + 1) / 2) ++levels;

  // Pull: coarse = weighted mean of (up to) 2 x 2 children, weight min(1, sum).
  int offset = 0;  // of the coarse level in the pyramid
  for (int k = 0; k < levels; ++k) {
    const int fs = level_size(n, k), cs = (fs + 1) / 2;
    __global const float4* fine =
        k == 0 ? texels + face * n * n : pyramid + offset - 6 * fs * fs + face * fs * fs;
    __global float4* coarse = pyramid + offset + face * cs * cs;
    for (int i = lid; i < cs * cs; i += size) {
      const int y = i / cs, x = i - y * cs;
      float3 sum = (float3)(0.0f);
      float wsum = 0.0f;
      for (int j = 0; j < 2; ++j) {
        const int fy = 2 * y + j;
        if (fy >= fs) break;
        for (int q = 0; q < 2; ++q) {
          const int fx = 2 * x + q;
          if (fx >= fs) break;
          const float4 t = fine[fy * fs + fx];
          const float w = level_weight(t, k == 0);
          sum += w * t.xyz;
          wsum += w;
        }
      }
      coarse[i] = wsum > 0.0f ? (float4)(sum / wsum, fmin(wsum, 1.0f)) : (float4)(0.0f);
    }
    barrier(CLK_GLOBAL_MEM_FENCE);
    offset += 6 * cs * cs;
  }
  if (lid == 0) {
    const float top = levels > 0 ? pyramid[offset - 6 + face].w : 0.0f;
    face_state[face] = pass == 0 ? (top > 0.0f ? 2 : 0) : 1;
  }

  // Push: a fine texel of weight w < 1 becomes w itself + (1 - w) its parent. On the keyframe
  // that leaves observed texels bit for bit, fills unobserved ones with the parent, and turns
  // this call's seeded borders (alpha < 0) back into unobserved (alpha 0) texels.
  for (int k = levels - 1; k >= 0; --k) {
    const int fs = level_size(n, k), cs = (fs + 1) / 2;
    offset -= 6 * cs * cs;
    __global float4* fine =
        k == 0 ? texels + face * n * n : pyramid + offset - 6 * fs * fs + face * fs * fs;
    __global const float4* coarse = pyramid + offset + face * cs * cs;
    for (int i = lid; i < fs * fs; i += size) {
      const int y = i / fs, x = i - y * fs;
      const float4 t = fine[i];
      const float4 parent = coarse[(y / 2) * cs + x / 2];
      if (k == 0) {
        if (t.w == 0.0f)
          fine[i] = (float4)(parent.xyz, 0.0f);
        else if (t.w < 0.0f)
          fine[i] = (float4)(t.xyz, 0.0f);
      } else if (t.w < 1.0f) {
        fine[i] = (float4)(t.w * t.xyz + (1.0f - t.w) * parent.xyz, 1.0f);
      }
    }
    barrier(CLK_GLOBAL_MEM_FENCE);
  }
}

// --- Across face edges ---

float3 cube_direction(int face, float u, float v) {
  const float sc = 2.0f * u - 1.0f, tc = 2.0f * v - 1.0f;
  switch (face) {
    case 0:
      return (float3)(1.0f, -tc, -sc);
    case 1:
      return (float3)(-1.0f, -tc, sc);
    case 2:
      return (float3)(sc, 1.0f, tc);
    case 3:
      return (float3)(sc, -1.0f, -tc);
    case 4:
      return (float3)(sc, -tc, 1.0f);
    default:
      return (float3)(-sc, -tc, -1.0f);
  }
}

// Direction -> face and texel (core/cubemap.cpp's cube_texel_from_direction).
int cube_texel(float3 d, int n, int* tx, int* ty) {
  const float ax = fabs(d.x), ay = fabs(d.y), az = fabs(d.z);
  int face;
  float sc, tc, ma;
  if (ax >= ay && ax >= az) {
    ma = ax;
    if (d.x > 0.0f) {
      face = 0;
      sc = -d.z;
      tc = -d.y;
    } else {
      face = 1;
      sc = d.z;
      tc = -d.y;
    }
  } else if (ay >= az) {
    ma = ay;
    if (d.y > 0.0f) {
      face = 2;
      sc = d.x;
      tc = d.z;
    } else {
      face = 3;
      sc = d.x;
      tc = -d.z;
    }
  } else {
    ma = az;
    if (d.z > 0.0f) {
      face = 4;
      sc = d.x;
      tc = -d.y;
    } else {
      face = 5;
      sc = -d.x;
      tc = -d.y;
    }
  }
  const float u = 0.5f * (sc / ma + 1.0f), v = 0.5f * (tc / ma + 1.0f);
  *tx = clamp((int)(u * (float)n), 0, n - 1);
  *ty = clamp((int)(v * (float)n), 0, n - 1);
  return face;
}

// Seeds the border texels of every face without data that has a neighbour with data, from
// the edge texels of those neighbours (face_state != 0): the texel one step outside the face's
// edge, looked up by direction, marked alpha = -1; records the faces it seeded in face_target
// for the pass that follows. Work-items: (i, face * 4 + edge); edges 0/1 are the top/bottom
// rows (corners included), 2/3 the left/right columns without the corners (one writer per
// texel).
__kernel void seed_borders(__global float4* texels, int n, __global const int* face_state,
                           __global int* face_target) {
  const int i = get_global_id(0), fe = get_global_id(1);
  if (i >= n || fe >= 24) return;
  const int face = fe / 4, edge = fe - 4 * face;
  int have = 0;
  for (int f = 0; f < 6; ++f) have |= face_state[f] != 0 ? 1 << f : 0;
  const int adjacent = 0x3F & ~(3 << (face & ~1));
  const int target = !((have >> face) & 1) && (adjacent & have) ? 1 : 0;
  if (i == 0 && edge == 0) face_target[face] = target;
  if (!target) return;
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
  if (source == face || !((have >> source) & 1)) return;
  const float4 s = texels[(source * n + sy) * n + sx];
  texels[(face * n + y) * n + x] = (float4)(s.xyz, -1.0f);
}
