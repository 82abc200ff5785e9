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

// A fine texel after the push from its parent, as selects (the keyframe's alpha pattern made
// the branches mispredict): see pull_push_face.
float4 push_texel(float4 t, float4 parent, int is_texels) {
  // Vector masks (isequal / isless on .wwww) so that the compiler blends instead of branching.
  if (is_texels) {
    const float4 filled = select(t, (float4)(parent.xyz, 0.0f), isequal(t.wwww, (float4)(0.0f)));
    return select(filled, (float4)(t.xyz, 0.0f), isless(t.wwww, (float4)(0.0f)));
  }
  const float4 mixed = (float4)(t.w * t.xyz + (1.0f - t.w) * parent.xyz, 1.0f);
  return select(t, mixed, isless(t.wwww, (float4)(1.0f)));
}

// Steps a work-item's texel (x, y) of a row-major grid m wide from index i to i + size
// without a division (dx, dy = size % m, size / m): integer division was the push's hottest
// instruction on PoCL.
#define NEXT_XY(x, y, m, dx, dy) \
  {                              \
    x += dx;                     \
    y += dy;                     \
    if (x >= m) {                \
      x -= m;                    \
      ++y;                       \
    }                            \
  }

// One work-group runs a face's whole pyramid, pull then push, with barriers between levels
// (every work-item of the group must call it). Returns the weight of the face's 1 x 1 top:
// > 0 when the face had data. Work-items own coarse texels: the pull reads their (up to) 2 x 2
// children, the push writes them from the one parent.
float pull_push_face(__global float4* texels, int n, __global float4* pyramid, int face, int lid,
                     int size) {
  int levels = 0;
  for (int m = n; m > 1; m = (m + 1) / 2) ++levels;

  // Pull: coarse = weighted mean of (up to) 2 x 2 children, weight min(1, sum).
  int offset = 0;  // of the coarse level in the pyramid
  for (int k = 0; k < levels; ++k) {
    const int fs = level_size(n, k), cs = (fs + 1) / 2;
    __global const float4* fine =
        k == 0 ? texels + face * n * n : pyramid + offset - 6 * fs * fs + face * fs * fs;
    __global float4* coarse = pyramid + offset + face * cs * cs;
    const int dy = size / cs, dx = size - dy * cs;
    int y = lid / cs, x = lid - y * cs;
    for (int i = lid; i < cs * cs; i += size) {
      float3 sum = (float3)(0.0f);
      float wsum = 0.0f;
      if (2 * x + 1 < fs && 2 * y + 1 < fs) {  // all four children: no loop, no branch
        __global const float4* c0 = fine + 2 * y * fs + 2 * x;
        const float4 a = c0[0], b = c0[1], c = c0[fs], d = c0[fs + 1];
        const float wa = level_weight(a, k == 0), wb = level_weight(b, k == 0);
        const float wc = level_weight(c, k == 0), wd = level_weight(d, k == 0);
        sum = ((wa * a.xyz + wb * b.xyz) + wc * c.xyz) + wd * d.xyz;
        wsum = ((wa + wb) + wc) + wd;
      } else {  // the last row or column of an odd-sized level
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
      }
      coarse[i] = wsum > 0.0f ? (float4)(sum / wsum, fmin(wsum, 1.0f)) : (float4)(0.0f);
      NEXT_XY(x, y, cs, dx, dy)
    }
    barrier(CLK_GLOBAL_MEM_FENCE);
    offset += 6 * cs * cs;
  }
  const float top = levels > 0 ? pyramid[offset - 6 + face].w : 0.0f;

  // Push: a fine texel of weight w < 1 becomes w itself + (1 - w) its parent. On the keyframe
  // that leaves observed texels bit for bit, fills unobserved ones with the parent, and turns
  // this call's seeded borders (alpha < 0) back into unobserved (alpha 0) texels.
  for (int k = levels - 1; k >= 0; --k) {
    const int fs = level_size(n, k), cs = (fs + 1) / 2;
    offset -= 6 * cs * cs;
    __global float4* fine =
        k == 0 ? texels + face * n * n : pyramid + offset - 6 * fs * fs + face * fs * fs;
    __global const float4* coarse = pyramid + offset + face * cs * cs;
    const int dy = size / cs, dx = size - dy * cs;
    int y = lid / cs, x = lid - y * cs;
    for (int i = lid; i < cs * cs; i += size) {
      const float4 parent = coarse[i];
      for (int j = 0; j < 2; ++j) {
        const int fy = 2 * y + j;
        if (fy >= fs) break;
        for (int q = 0; q < 2; ++q) {
          const int fx = 2 * x + q;
          if (fx >= fs) break;
          __global float4* f = fine + fy * fs + fx;
          *f = push_texel(*f, parent, k == 0);
        }
      }
      NEXT_XY(x, y, cs, dx, dy)
    }
    barrier(CLK_GLOBAL_MEM_FENCE);
  }
  return top;
}

// Pass 0: one work-group per face. face_state[f]: 0 = no data, 2 = observed texels (later,
// fill_empty_faces: 1 = filled from neighbours).
__kernel void pull_push_faces(__global float4* texels, int n, __global float4* pyramid,
                              __global int* face_state) {
  const int face = get_group_id(0), lid = get_local_id(0);
  const float top = pull_push_face(texels, n, pyramid, face, lid, get_local_size(0));
  if (lid == 0) face_state[face] = top > 0.0f ? 2 : 0;
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

// Seeds border texel i of edge `edge` of `face` (a face without data) from the texel one step
// outside the face's edge in the adjacent face, looked up by direction, when that face has
// data (bit set in `have`); marked alpha = -1 for the pull-push that follows. Edges 0/1 are
// the top/bottom rows (corners included), 2/3 the left/right columns without the corners (one
// writer per texel).
void seed_border_texel(__global float4* texels, int n, int face, int edge, int i, int have) {
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

// Passes 1..3 in one work-group (after pull_push_faces): each pass seeds the borders of the
// faces without data that have a neighbour with data, pulls and pushes them, and marks them
// filled (face_state 1); a face opposite the only observed one needs its four neighbours
// filled first, hence up to three passes. One launch instead of six: on PoCL a launch cost
// about as much as a pass's work, and the usual pass (the floor of an upward fisheye) is one
// face (docs/performance.md "Light capture: bench light").
__kernel void fill_empty_faces(__global float4* texels, int n, __global float4* pyramid,
                               __global int* face_state) {
  const int lid = get_local_id(0), size = get_local_size(0);
  for (int pass = 1; pass <= 3; ++pass) {
    int have = 0;
    for (int f = 0; f < 6; ++f) have |= face_state[f] != 0 ? 1 << f : 0;
    int targets = 0;
    for (int f = 0; f < 6; ++f) {
      const int adjacent = 0x3F & ~(3 << (f & ~1));
      if (!((have >> f) & 1) && (adjacent & have)) targets |= 1 << f;
    }
    if (targets == 0) return;  // the same for every work-item: they read the same state
    for (int j = lid; j < 24 * n; j += size) {
      const int fe = j / n, face = fe / 4;
      if ((targets >> face) & 1)
        seed_border_texel(texels, n, face, fe - 4 * face, j - fe * n, have);
    }
    barrier(CLK_GLOBAL_MEM_FENCE);
    for (int f = 0; f < 6; ++f)
      if ((targets >> f) & 1) pull_push_face(texels, n, pyramid, f, lid, size);
    if (lid == 0)
      for (int f = 0; f < 6; ++f)
        if ((targets >> f) & 1) face_state[f] = 1;
    barrier(CLK_GLOBAL_MEM_FENCE);
  }
}
