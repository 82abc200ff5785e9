// Reprojection of an environment-map keyframe to another position through the room box
// (docs/light-capture.md "Parallax"). One work-item per target texel (x, face * m + y),
// samples x samples sub-texel directions from the target position: each hits the box at a
// wall point, which the keyframe saw along the direction from its own position; the nearest
// keyframe texel there is averaged in. A target texel is observed (alpha 1) only when every
// keyframe texel it drew from is (alpha > 0); filled texels still give their rgb, as the SH
// needs the whole sphere. keyframe_reprojection_reference.cpp mirrors every step in float.
#pragma OPENCL FP_CONTRACT OFF

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

// Direction -> the texel of an n-px cube that contains it (envmap_types.cpp cube_texel_of).
int cube_texel(float3 d, int n, int* tx, int* ty) {
  const float ax = fabs(d.x), ay = fabs(d.y), az = fabs(d.z);
  int face;
  float sc, tc, ma;
  if (ax >= ay && ax >= az) {
    ma = ax;
    face = d.x > 0.0f ? 0 : 1;
    sc = d.x > 0.0f ? -d.z : d.z;
    tc = -d.y;
  } else if (ay >= az) {
    ma = ay;
    face = d.y > 0.0f ? 2 : 3;
    sc = d.x;
    tc = d.y > 0.0f ? d.z : -d.z;
  } else {
    ma = az;
    face = d.z > 0.0f ? 4 : 5;
    sc = d.z > 0.0f ? d.x : -d.x;
    tc = -d.y;
  }
  const float u = 0.5f * (sc / ma + 1.0f), v = 0.5f * (tc / ma + 1.0f);
  *tx = clamp((int)(u * (float)n), 0, n - 1);
  *ty = clamp((int)(v * (float)n), 0, n - 1);
  return face;
}

// box_lo, box_hi: the room box relative to the target position; offset: target - keyframe.
// parallax 0: directions are kept (a plain box filter, for a keyframe or target outside the
// box).
__kernel void reproject_keyframe(__global const float4* texels, int n, __global float4* out, int m,
                                 int samples, int parallax, float4 box_lo, float4 box_hi,
                                 float4 offset) {
  const int x = get_global_id(0), row = get_global_id(1);
  if (x >= m || row >= 6 * m) return;
  const int face = row / m, y = row - face * m;
  const float inv = 1.0f / (float)(m * samples);
  float3 sum = (float3)(0.0f);
  int all = 1;
  for (int j = 0; j < samples; ++j)
    for (int i = 0; i < samples; ++i) {
      const float u = ((float)(x * samples + i) + 0.5f) * inv;
      const float v = ((float)(y * samples + j) + 0.5f) * inv;
      const float3 d = cube_direction(face, u, v);
      float3 w = d;
      if (parallax) {
        const float3 tm = fmax(box_lo.xyz / d, box_hi.xyz / d);
        const float t = fmin(tm.x, fmin(tm.y, tm.z));
        w = offset.xyz + t * d;
      }
      int tx, ty;
      const int f = cube_texel(w, n, &tx, &ty);
      const float4 s = texels[(f * n + ty) * n + tx];
      sum += s.xyz;
      all &= s.w > 0.0f ? 1 : 0;
    }
  out[row * m + x] = (float4)(sum / (float)(samples * samples), all ? 1.0f : 0.0f);
}
