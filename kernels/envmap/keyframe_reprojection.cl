// Reprojection of an environment-map keyframe to another position through the room box
// (docs/light-capture.md "Parallax"). One work-item per target texel (x, face * m + y),
// samples x samples sub-texel directions from the target position: each hits the box at a
// wall point, which the keyframe saw along the direction from its own position; the keyframe
// is sampled there bilinearly within the face (clamped at its edges) and the samples are
// averaged. Bilinear rather than nearest: a point nearer the object than the keyframe (the
// window, 1.9 m from the sim's object and 3.6 m from the keyframe) is magnified, and nearest
// lookups shifted its structure by up to half a keyframe texel (eval light: 0.079 -> ...).
// A target texel is observed (alpha 1) only when every keyframe texel it drew from is
// (alpha > 0); filled texels still give their rgb, as the SH needs the whole sphere.
// keyframe_reprojection_reference.cpp mirrors every step in float.
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

// Direction -> face and face coordinates u, v (envmap_types.cpp cube_coord_of).
int cube_coord(float3 d, float* u, float* v) {
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
  *u = 0.5f * (sc / ma + 1.0f);
  *v = 0.5f * (tc / ma + 1.0f);
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
      float fu, fv;
      const int f = cube_coord(w, &fu, &fv);
      // Bilinear at texel centres, the footprint clamped into the face.
      const float px = fu * (float)n - 0.5f, py = fv * (float)n - 0.5f;
      const float x0f = floor(px), y0f = floor(py);
      const float ax = px - x0f, ay = py - y0f;
      const int x0 = clamp((int)x0f, 0, n - 1), y0 = clamp((int)y0f, 0, n - 1);
      const int x1 = clamp((int)x0f + 1, 0, n - 1), y1 = clamp((int)y0f + 1, 0, n - 1);
      __global const float4* face_texels = texels + f * n * n;
      const float4 a = face_texels[y0 * n + x0], b = face_texels[y0 * n + x1];
      const float4 c = face_texels[y1 * n + x0], e = face_texels[y1 * n + x1];
      const float3 top = a.xyz + ax * (b.xyz - a.xyz), bottom = c.xyz + ax * (e.xyz - c.xyz);
      sum += top + ay * (bottom - top);
      // Every texel with a weight must be observed (ax, ay < 1: a always has one).
      const bool seen = a.w > 0.0f && (ax == 0.0f || b.w > 0.0f) && (ay == 0.0f || c.w > 0.0f) &&
                        (ax == 0.0f || ay == 0.0f || e.w > 0.0f);
      all &= seen ? 1 : 0;
    }
  out[row * m + x] = (float4)(sum / (float)(samples * samples), all ? 1.0f : 0.0f);
}
