// Environment-map keyframe update (thesis ch. 6; docs/light-capture.md). One work-item per
// cube texel (x, face * n + y): the texel's world direction, rotated into the fisheye's frame
// (rotation only: distant light), projected through the Kannala-Brandt model, bilinearly
// sampled from the HDR-converted image (rgb = radiance, a = quality, 0 = never use), then
// merged by the selected rule. envmap_update_reference.cpp mirrors every step in float.
#define RULE_KALMAN 0
#define RULE_BEST_SCORE 1

// OpenGL cube map face coordinates -> direction (not normalised; core/cubemap.cpp).
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

// atan2(r, z) for r >= 0, in [0, pi]: Abramowitz & Stegun 4.4.49 (|error| <= 2e-8 rad on
// [0, 1]; 1e-5 px at the sim's 1024 px fisheye) after an octant reduction. PoCL's atan2 took
// 60 % of the kernel's time; envmap_update_reference.cpp evaluates the same polynomial.
float polar_angle(float r, float z) {
  const float az = fabs(z);
  const float hi = fmax(r, az), lo = fmin(r, az);
  const float x = hi > 0.0f ? lo / hi : 0.0f, x2 = x * x;
  float a =
      x *
      (1.0f + x2 * (-0.3333314528f +
                    x2 * (0.1999355085f +
                          x2 * (-0.1420889944f +
                                x2 * (0.1065626393f +
                                      x2 * (-0.0752896400f +
                                            x2 * (0.0429096138f +
                                                  x2 * (-0.0161657367f + x2 * 0.0028662257f))))))));
  a = r > az ? M_PI_2_F - a : a;
  return z < 0.0f ? M_PI_F - a : a;
}

// Kannala-Brandt projection (core/camera/kannala_brandt.cpp); false beyond max_theta.
bool project_kb(float3 p, float4 f, float4 k, float max_theta, float2* px) {
  const float r = sqrt(p.x * p.x + p.y * p.y);
  const float theta = polar_angle(r, p.z);
  if (!(theta <= max_theta)) return false;
  if (r == 0.0f) {
    *px = (float2)(f.z, f.w);
    return p.z > 0.0f;
  }
  const float t2 = theta * theta;
  const float theta_d = theta * (1.0f + t2 * (k.x + t2 * (k.y + t2 * (k.z + t2 * k.w))));
  const float s = theta_d / r;
  *px = (float2)(f.x * s * p.x + f.z, f.y * s * p.y + f.w);
  return true;
}

// Bilinear sample at pixel centres on integers; false unless all four neighbours are inside
// the image and usable (quality > 0): a saturated or black pixel must not leak into a texel.
bool sample_bilinear(__global const float4* image, int width, int height, float2 px, float4* out) {
  const float fx0 = floor(px.x), fy0 = floor(px.y);
  const int x0 = (int)fx0, y0 = (int)fy0;
  if (!(fx0 >= 0.0f && fy0 >= 0.0f && x0 + 1 < width && y0 + 1 < height)) return false;
  const float ax = px.x - fx0, ay = px.y - fy0;
  const int i = y0 * width + x0;
  const float4 a = image[i], b = image[i + 1], c = image[i + width], d = image[i + width + 1];
  if (!(a.w > 0.0f && b.w > 0.0f && c.w > 0.0f && d.w > 0.0f)) return false;
  const float4 top = a + ax * (b - a), bottom = c + ax * (d - c);
  *out = top + ay * (bottom - top);
  return true;
}

float luminance(float4 v) {
  return 0.2126f * v.x + 0.7152f * v.y + 0.0722f * v.z;
}

__kernel void envmap_update(__global float4* texels, __global float4* pending,
                            __global const float4* image, int width, int height, int n, float4 r0,
                            float4 r1, float4 r2, float4 focal_centre, float4 k, float max_theta,
                            int rule, int publish, float measurement_var, float process_var,
                            float change_sigma2) {
  const int x = get_global_id(0), row = get_global_id(1);
  if (x >= n || row >= 6 * n) return;
  const int face = row / n, y = row - face * n;
  const float inv_n = 1.0f / (float)n;
  const float3 d = cube_direction(face, ((float)x + 0.5f) * inv_n, ((float)y + 0.5f) * inv_n);
  const float3 c = (float3)(dot(r0.xyz, d), dot(r1.xyz, d), dot(r2.xyz, d));
  float2 px;
  float4 z = (float4)(0.0f);
  const bool ok = project_kb(c, focal_centre, k, max_theta, &px) &&
                  sample_bilinear(image, width, height, px, &z);
  const int i = row * n + x;

  if (rule == RULE_KALMAN) {
    if (!ok) return;
    float4 t = texels[i];
    const float s = measurement_var / z.w;
    if (!(t.w > 0.0f)) {
      t = (float4)(z.xyz, s);  // first observation replaces
    } else {
      const float cvar = t.w + process_var;  // predict
      const float lx = fmax(luminance(t), 1e-30f);
      const float e = (luminance(z) - lx) / lx;
      if (change_sigma2 > 0.0f && e * e > change_sigma2 * (cvar + s)) {
        t = (float4)(z.xyz, s);  // the light changed: start again
      } else {
        const float g = cvar / (cvar + s);
        t = (float4)(t.xyz + g * (z.xyz - t.xyz), (1.0f - g) * cvar);
      }
    }
    texels[i] = t;
  } else {
    float4 p = pending[i];
    if (ok && z.w > p.w) p = z;
    if (publish) {
      if (p.w > 0.0f) texels[i] = p;
      pending[i] = (float4)(0.0f);
    } else {
      pending[i] = p;
    }
  }
}
