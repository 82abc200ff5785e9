// Environment-map keyframe update (thesis ch. 6; docs/light-capture.md). One work-item per
// cube texel (x, face * n + y): the texel's world direction (with a room box: the direction
// from the fisheye's centre to where the texel's ray from the keyframe's position leaves the
// box), rotated into the fisheye's frame, projected through the Kannala-Brandt model,
// bilinearly sampled, then merged by the selected rule. Two entry points differ only in what
// they sample: envmap_update_raw converts the four raw pixels it reads with the HDR
// conversion's own per-pixel function (convert_one; the program is hdr_conversion.cl followed
// by this file, whose FP_CONTRACT OFF then covers both), so a frame is never converted whole
// (98k texels read ~400k of a 1024 px frame's 1M pixels, and nothing is written back);
// envmap_update samples an already converted image. envmap_update_reference.cpp mirrors
// every step in float.
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

// Bilinear footprint at pixel centres on integers: the top-left pixel's index and the
// weights; false unless all four neighbours are inside the image.
bool footprint(int width, int height, float2 px, int* i, float2* w) {
  const float fx0 = floor(px.x), fy0 = floor(px.y);
  const int x0 = (int)fx0, y0 = (int)fy0;
  if (!(fx0 >= 0.0f && fy0 >= 0.0f && x0 + 1 < width && y0 + 1 < height)) return false;
  *w = (float2)(px.x - fx0, px.y - fy0);
  *i = y0 * width + x0;
  return true;
}

// False unless all four samples are usable (quality > 0): a saturated, black or
// out-of-circle pixel must not leak into a texel.
bool blend(float4 a, float4 b, float4 c, float4 d, float2 w, float4* out) {
  if (!(a.w > 0.0f && b.w > 0.0f && c.w > 0.0f && d.w > 0.0f)) return false;
  const float4 top = a + w.x * (b - a), bottom = c + w.x * (d - c);
  *out = top + w.y * (bottom - top);
  return true;
}

float luminance(float4 v) {
  return 0.2126f * v.x + 0.7152f * v.y + 0.0722f * v.z;
}

// Where texel i's fisheye sample lands: its direction (box-projected when parallax is on),
// rotated into the camera and projected. false: the fisheye does not see it.
bool texel_pixel(int n, int row, int x, float4 r0, float4 r1, float4 r2, float4 focal_centre,
                 float4 k, float max_theta, int parallax, float4 box_lo, float4 box_hi,
                 float4 offset, float2* px) {
  const int face = row / n, y = row - face * n;
  const float inv_n = 1.0f / (float)n;
  const float3 d = cube_direction(face, ((float)x + 0.5f) * inv_n, ((float)y + 0.5f) * inv_n);
  float3 w = d;
  if (parallax) {
    // Exit of the ray k + t d from the box (box_lo, box_hi relative to k; k inside, so every
    // axis gives t >= 0 or +inf, and the major axis a finite one); then the wall point seen
    // from the fisheye: (k - c) + t d. envmap_types.cpp's box_exit / parallax_direction.
    const float3 tl = box_lo.xyz / d, th = box_hi.xyz / d;
    const float3 tm = fmax(tl, th);
    const float t = fmin(tm.x, fmin(tm.y, tm.z));
    w = offset.xyz + t * d;
  }
  const float3 c = (float3)(dot(r0.xyz, w), dot(r1.xyz, w), dot(r2.xyz, w));
  return project_kb(c, focal_centre, k, max_theta, px);
}

// The update rules on texel i with sample z (ok: there is a usable sample).
void merge(__global float4* texels, __global float4* pending, int i, bool ok, float4 z, int rule,
           int publish, float measurement_var, float process_var, float change_sigma2) {
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

// From an HDR-converted image (rgb radiance, a quality, 0 = unusable).
__kernel void envmap_update(__global float4* texels, __global float4* pending,
                            __global const float4* image, int width, int height, int n, float4 r0,
                            float4 r1, float4 r2, float4 focal_centre, float4 k, float max_theta,
                            int parallax, float4 box_lo, float4 box_hi, float4 offset, int rule,
                            int publish, float measurement_var, float process_var,
                            float change_sigma2) {
  const int x = get_global_id(0), row = get_global_id(1);
  if (x >= n || row >= 6 * n) return;
  float2 px, w;
  int i0;
  float4 z = (float4)(0.0f);
  const bool ok = texel_pixel(n, row, x, r0, r1, r2, focal_centre, k, max_theta, parallax, box_lo,
                              box_hi, offset, &px) &&
                  footprint(width, height, px, &i0, &w) &&
                  blend(image[i0], image[i0 + 1], image[i0 + width], image[i0 + width + 1], w, &z);
  merge(texels, pending, row * n + x, ok, z, rule, publish, measurement_var, process_var,
        change_sigma2);
}

// From the raw frame (RGB16, linear, not shifted): the four pixels of the footprint converted
// as hdr_conversion does (same constants from hdr_conversion_constants, same convert_one).
__kernel void envmap_update_raw(__global float4* texels, __global float4* pending,
                                __global const ushort* raw, int width, int height, int black_level,
                                int saturated_signal, int black_margin, float radiance_scale,
                                float inv_range, int crop, float circle_cx, float circle_cy,
                                float circle_radius2, int n, float4 r0, float4 r1, float4 r2,
                                float4 focal_centre, float4 k, float max_theta, int parallax,
                                float4 box_lo, float4 box_hi, float4 offset, int rule, int publish,
                                float measurement_var, float process_var, float change_sigma2) {
  const int x = get_global_id(0), row = get_global_id(1);
  if (x >= n || row >= 6 * n) return;
  float2 px, w;
  int i0;
  float4 z = (float4)(0.0f);
  bool ok = texel_pixel(n, row, x, r0, r1, r2, focal_centre, k, max_theta, parallax, box_lo, box_hi,
                        offset, &px) &&
            footprint(width, height, px, &i0, &w);
  if (ok) {
    const int y0 = i0 / width, x0 = i0 - y0 * width;
    float4 q[4];
    for (int j = 0; j < 4; ++j) {
      const int xi = x0 + (j & 1), yi = y0 + (j >> 1), i = yi * width + xi;
      q[j] = convert_one((int)raw[3 * i] - black_level, (int)raw[3 * i + 1] - black_level,
                         (int)raw[3 * i + 2] - black_level, xi, yi, saturated_signal, black_margin,
                         radiance_scale, inv_range, crop, circle_cx, circle_cy, circle_radius2);
    }
    ok = blend(q[0], q[1], q[2], q[3], w, &z);
  }
  merge(texels, pending, row * n + x, ok, z, rule, publish, measurement_var, process_var,
        change_sigma2);
}
