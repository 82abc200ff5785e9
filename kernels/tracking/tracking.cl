// Dense RGB-D tracking on the device, the twin of frame_pyramid.cpp (the pyramid) and
// normal_equations.cpp (one Gauss-Newton iteration's sums). LOCAL (a -D option) is the
// work-group size of accumulate_normal_equations.
#ifndef LOCAL
#error "build with -DLOCAL=<work-group size>"
#endif

#define SUMS 40
#define PT_STRIDE 24

typedef struct {
  float r[9];
  float t[3];
  float fx, fy, cx, cy;
  float inv_gain, bias;
  float inv_var_photo, inv_var_geo;
  float nu;
  float photo_inlier, geo_inlier;
  float min_depth;
  float readout_rotation[3];
  float pad;
} IterationParams;

inline float luma(__global const uchar* rgb) {
  return 0.299f * rgb[0] + 0.587f * rgb[1] + 0.114f * rgb[2];
}

inline float metres(ushort mm, float min_m, float max_m) {
  const float z = (float)mm * 0.001f;
  return z >= min_m && z <= max_m ? z : 0.0f;
}

// frame_pyramid.cpp block_depth: the mean of the valid samples within 5% of the nearest.
inline float block_depth(float d0, float d1, float d2, float d3) {
  float nearest = 0.0f;
  if (d0 > 0.0f && (nearest == 0.0f || d0 < nearest)) nearest = d0;
  if (d1 > 0.0f && (nearest == 0.0f || d1 < nearest)) nearest = d1;
  if (d2 > 0.0f && (nearest == 0.0f || d2 < nearest)) nearest = d2;
  if (d3 > 0.0f && (nearest == 0.0f || d3 < nearest)) nearest = d3;
  if (nearest == 0.0f) return 0.0f;
  const float bound = nearest * 1.05f;
  float sum = 0.0f;
  int count = 0;
  if (d0 > 0.0f && d0 <= bound) {
    sum += d0;
    ++count;
  }
  if (d1 > 0.0f && d1 <= bound) {
    sum += d1;
    ++count;
  }
  if (d2 > 0.0f && d2 <= bound) {
    sum += d2;
    ++count;
  }
  if (d3 > 0.0f && d3 <= bound) {
    sum += d3;
    ++count;
  }
  return sum / (float)count;
}

// The finest level from the frame: factor 1 (full) or 2 (2x2 average).
__kernel void finest_level(__global const uchar* colour, __global const ushort* depth_mm,
                           int frame_width, int factor, float min_m, float max_m,
                           __global float* intensity, __global float* depth_m, int width,
                           int height) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int i = y * width + x;
  if (factor == 1) {
    const int s = y * frame_width + x;
    intensity[i] = luma(colour + 3 * s);
    depth_m[i] = metres(depth_mm[s], min_m, max_m);
    return;
  }
  const int s = 2 * y * frame_width + 2 * x;
  __global const uchar* a = colour + 3 * s;
  __global const uchar* b = colour + 3 * (s + frame_width);
  const int r = a[0] + a[3] + b[0] + b[3], g = a[1] + a[4] + b[1] + b[4],
            bl = a[2] + a[5] + b[2] + b[5];
  intensity[i] = 0.25f * (0.299f * (float)r + 0.587f * (float)g + 0.114f * (float)bl);
  depth_m[i] = block_depth(metres(depth_mm[s], min_m, max_m), metres(depth_mm[s + 1], min_m, max_m),
                           metres(depth_mm[s + frame_width], min_m, max_m),
                           metres(depth_mm[s + frame_width + 1], min_m, max_m));
}

// frame_pyramid.cpp undistort_level: intensity bilinear, depth nearest; outside: no depth.
__kernel void undistort(__global const float* in_intensity, __global const float* in_depth,
                        __global const float* map, __global float* intensity,
                        __global float* depth_m, int width, int height) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int i = y * width + x;
  const float u = map[2 * i], v = map[2 * i + 1];
  if (!(u >= 0.0f && v >= 0.0f && u <= (float)(width - 1) && v <= (float)(height - 1))) {
    intensity[i] = in_intensity[i];
    depth_m[i] = 0.0f;
    return;
  }
  const int x0 = min((int)u, width - 2), y0 = min((int)v, height - 2);
  const float ax = u - (float)x0, ay = v - (float)y0;
  __global const float* r0 = in_intensity + y0 * width + x0;
  __global const float* r1 = r0 + width;
  intensity[i] =
      (1.0f - ay) * ((1.0f - ax) * r0[0] + ax * r0[1]) + ay * ((1.0f - ax) * r1[0] + ax * r1[1]);
  depth_m[i] = in_depth[(int)(v + 0.5f) * width + (int)(u + 0.5f)];
}

__kernel void halve(__global const float* in_intensity, __global const float* in_depth,
                    int in_width, __global float* intensity, __global float* depth_m, int width,
                    int height) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int s = 2 * y * in_width + 2 * x;
  intensity[y * width + x] = 0.25f * (in_intensity[s] + in_intensity[s + 1] +
                                      in_intensity[s + in_width] + in_intensity[s + in_width + 1]);
  depth_m[y * width + x] =
      block_depth(in_depth[s], in_depth[s + 1], in_depth[s + in_width], in_depth[s + in_width + 1]);
}

inline void add_residual(float* acc, __global const float* j, float r, float weight) {
  int k = 0;
  for (int a = 0; a < 6; ++a) {
    const float wa = weight * j[a];
    for (int b = a; b < 6; ++b) acc[k++] += wa * j[b];
    acc[21 + a] += wa * r;
  }
}

inline float bilinear(__global const float* img, int width, float u, float v) {
  const int x0 = (int)floor(u), y0 = (int)floor(v);
  const float fx = u - (float)x0, fy = v - (float)y0;
  __global const float* r0 = img + y0 * width + x0;
  __global const float* r1 = r0 + width;
  return (1.0f - fy) * ((1.0f - fx) * r0[0] + fx * r0[1]) + fy * ((1.0f - fx) * r1[0] + fx * r1[1]);
}

// Each work-item sums its share of the points privately, then the work-group adds the items'
// sums (one item per sum) into partial[group][SUMS]; the host adds the groups.
__kernel __attribute__((reqd_work_group_size(LOCAL, 1, 1))) void accumulate_normal_equations(
    __global const float* points, int count, __global const float* intensity,
    __global const float* depth_m, int width, int height, IterationParams p,
    __global float* partial) {
  __local float shared[LOCAL * SUMS];
  float acc[SUMS];
  for (int k = 0; k < SUMS; ++k) acc[k] = 0.0f;
  for (int i = get_global_id(0); i < count; i += get_global_size(0)) {
    __global const float* pt = points + i * PT_STRIDE;
    const float X0 = p.r[0] * pt[0] + p.r[1] * pt[1] + p.r[2] * pt[2] + p.t[0];
    const float Y0 = p.r[3] * pt[0] + p.r[4] * pt[1] + p.r[5] * pt[2] + p.t[1];
    const float Z0 = p.r[6] * pt[0] + p.r[7] * pt[1] + p.r[8] * pt[2] + p.t[2];
    if (!(Z0 >= p.min_depth)) continue;
    float u = p.fx * X0 / Z0 + p.cx, v = p.fy * Y0 / Z0 + p.cy;
    float X = X0, Y = Y0, Z = Z0;
    if (p.readout_rotation[0] != 0.0f || p.readout_rotation[1] != 0.0f ||
        p.readout_rotation[2] != 0.0f) {
      // Rolling shutter, as normal_equations.cpp.
      const float s = v / (float)height - 0.5f;
      const float a = -s * p.readout_rotation[0], b = -s * p.readout_rotation[1],
                  c = -s * p.readout_rotation[2];
      X = X0 + (b * Z0 - c * Y0);
      Y = Y0 + (c * X0 - a * Z0);
      Z = Z0 + (a * Y0 - b * X0);
      if (!(Z >= p.min_depth)) continue;
      u = p.fx * X / Z + p.cx;
      v = p.fy * Y / Z + p.cy;
    }
    if (!(u >= 0.0f && v >= 0.0f && u < (float)(width - 1) && v < (float)(height - 1))) continue;
    acc[33] += 1.0f;

    const float current = bilinear(intensity, width, u, v);
    const float rp = (current - p.bias) * p.inv_gain - pt[3];
    const float tp = (p.nu + 1.0f) / (p.nu + rp * rp * p.inv_var_photo);
    add_residual(acc, pt + 8, rp, tp * p.inv_var_photo);
    acc[27] += 1.0f;
    acc[28] += tp * rp * rp;
    acc[29] += rp * rp;
    acc[35] += tp;
    acc[36] += tp * pt[3];
    acc[37] += tp * current;
    acc[38] += tp * pt[3] * pt[3];
    acc[39] += tp * current * current;
    bool inlier = fabs(rp) <= p.photo_inlier;

    if (pt[7] > 0.0f) {
      const int ui = (int)(u + 0.5f), vi = (int)(v + 0.5f);
      const float zc = depth_m[vi * width + ui];
      if (zc > 0.0f) {
        const float qx = ((float)ui - p.cx) / p.fx * zc - X;
        const float qy = ((float)vi - p.cy) / p.fy * zc - Y;
        const float qz = zc - Z;
        const float nx = p.r[0] * pt[4] + p.r[1] * pt[5] + p.r[2] * pt[6];
        const float ny = p.r[3] * pt[4] + p.r[4] * pt[5] + p.r[5] * pt[6];
        const float nz = p.r[6] * pt[4] + p.r[7] * pt[5] + p.r[8] * pt[6];
        const float rg = (nx * qx + ny * qy + nz * qz) * pt[20];
        const float tg = (p.nu + 1.0f) / (p.nu + rg * rg * p.inv_var_geo);
        add_residual(acc, pt + 14, rg, tg * p.inv_var_geo);
        acc[30] += 1.0f;
        acc[31] += tg * rg * rg;
        acc[32] += rg * rg;
        inlier = inlier && fabs(rg) <= p.geo_inlier;
      }
    }
    if (inlier) acc[34] += 1.0f;
  }
  const int lid = get_local_id(0);
  for (int k = 0; k < SUMS; ++k) shared[lid * SUMS + k] = acc[k];
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid < SUMS) {
    float total = 0.0f;
    for (int l = 0; l < LOCAL; ++l) total += shared[l * SUMS + lid];
    partial[get_group_id(0) * SUMS + lid] = total;
  }
}

// keyframe.cpp select_points + make_point: one work-item per block writes its point (the
// pixel of largest gradient with depth) into points[block], valid = 0 when it has none.
#define NORMAL_MAX_DEPTH_STEP 0.1f
#define NORMAL_MIN_COS 0.2f

inline float3 backproject(float x, float y, float z, float4 k) {
  return (float3)((x - k.z) / k.x * z, (y - k.w) / k.y * z, z);
}

__kernel void select_points(__global const float* intensity, __global const float* depth_m,
                            int width, int height, float4 k /* fx fy cx cy */, int block,
                            int blocks_x, int blocks_y, __global float* points) {
  const int b = get_global_id(0);
  if (b >= blocks_x * blocks_y) return;
  const int bx = 1 + (b % blocks_x) * block, by = 1 + (b / blocks_x) * block;
  __global float* out = points + b * PT_STRIDE;
  for (int i = 0; i < PT_STRIDE; ++i) out[i] = 0.0f;
  int best_x = -1, best_y = -1;
  float best_g2 = -1.0f, best_gx = 0.0f, best_gy = 0.0f;
  for (int y = by; y < min(by + block, height - 1); ++y)
    for (int x = bx; x < min(bx + block, width - 1); ++x) {
      const int i = y * width + x;
      if (!(depth_m[i] > 0.0f)) continue;
      const float gx = 0.5f * (intensity[i + 1] - intensity[i - 1]);
      const float gy = 0.5f * (intensity[i + width] - intensity[i - width]);
      const float g2 = gx * gx + gy * gy;
      if (g2 > best_g2) {
        best_g2 = g2;
        best_x = x;
        best_y = y;
        best_gx = gx;
        best_gy = gy;
      }
    }
  if (best_x < 0) return;
  const int i = best_y * width + best_x;
  const float z = depth_m[i];
  const float3 p = backproject((float)best_x, (float)best_y, z, k);
  out[0] = p.x;
  out[1] = p.y;
  out[2] = p.z;
  out[3] = intensity[i];
  const float jx = best_gx * k.x / z, jy = best_gy * k.y / z;
  const float3 jv = (float3)(jx, jy, -(jx * p.x + jy * p.y) / z);
  const float3 jw = cross(p, jv);
  out[8] = jv.x;
  out[9] = jv.y;
  out[10] = jv.z;
  out[11] = jw.x;
  out[12] = jw.y;
  out[13] = jw.z;
  const float inv_z2 = 1.0f / (z * z);
  out[20] = inv_z2;
  out[21] = 1.0f;

  const float zl = depth_m[i - 1], zr = depth_m[i + 1], zu = depth_m[i - width],
              zd = depth_m[i + width];
  const float step = NORMAL_MAX_DEPTH_STEP * z;
  if (!(zl > 0.0f) || fabs(zl - z) > step || !(zr > 0.0f) || fabs(zr - z) > step || !(zu > 0.0f) ||
      fabs(zu - z) > step || !(zd > 0.0f) || fabs(zd - z) > step)
    return;
  const float3 dx = backproject((float)(best_x + 1), (float)best_y, zr, k) -
                    backproject((float)(best_x - 1), (float)best_y, zl, k);
  const float3 dy = backproject((float)best_x, (float)(best_y + 1), zd, k) -
                    backproject((float)best_x, (float)(best_y - 1), zu, k);
  float3 n = cross(dx, dy);
  const float len = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  if (!(len > 0.0f)) return;
  n /= len;
  const float cosine =
      (n.x * p.x + n.y * p.y + n.z * p.z) / sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
  if (cosine > 0.0f) n = -n;
  if (!(fabs(cosine) >= NORMAL_MIN_COS)) return;
  const float3 pn = cross(p, n);
  out[4] = n.x;
  out[5] = n.y;
  out[6] = n.z;
  out[7] = 1.0f;
  out[14] = -n.x * inv_z2;
  out[15] = -n.y * inv_z2;
  out[16] = -n.z * inv_z2;
  out[17] = -pn.x * inv_z2;
  out[18] = -pn.y * inv_z2;
  out[19] = -pn.z * inv_z2;
}
