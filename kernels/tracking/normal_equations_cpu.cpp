// accumulate_cpu: the reference's sums four keyframe points at a time. Each TrackPoint is 24
// floats, six 4-float groups, so four points transpose into the 24 fields as 4-lane vectors
// with six 4x4 transposes; the pixel reads (bilinear intensity, nearest depth) stay scalar
// per lane. GCC/Clang vector extensions: SSE2 on x86-64, NEON on arm64, no intrinsics.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "kernels/tracking/normal_equations.hpp"
#include "kernels/tracking/normal_equations_terms.hpp"

namespace probeless::tracking {
namespace {

using detail::add_residual;
using detail::bilinear;

using V = float __attribute__((vector_size(16)));
using M = int __attribute__((vector_size(16)));  // a comparison: -1 (true) or 0 per lane

constexpr int kLanes = 4;
// Four lanes of 16 groups: 64 points per float chunk, summed into double, as the reference.
constexpr std::size_t kGroupsPerChunk = 16;

V splat(float x) {
  return V{x, x, x, x};
}
V select(M mask, V a, V b) {
  return reinterpret_cast<V>((reinterpret_cast<M>(a) & mask) | (reinterpret_cast<M>(b) & ~mask));
}
V ones(M mask) {
  return select(mask, splat(1.0f), splat(0.0f));
}
V magnitude(V x) {
  return reinterpret_cast<V>(reinterpret_cast<M>(x) &
                             M{0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff});
}

#if defined(__clang__)
#define SHUFFLE(a, b, i, j, k, l) __builtin_shufflevector(a, b, i, j, k, l)
#else
#define SHUFFLE(a, b, i, j, k, l) __builtin_shuffle(a, b, M{i, j, k, l})
#endif

// Rows a..d (one 4-float group of four points) -> the group's four fields across the points.
void transpose(V a, V b, V c, V d, V* out) {
  const V t0 = SHUFFLE(a, b, 0, 4, 1, 5), t1 = SHUFFLE(a, b, 2, 6, 3, 7);
  const V t2 = SHUFFLE(c, d, 0, 4, 1, 5), t3 = SHUFFLE(c, d, 2, 6, 3, 7);
  out[0] = SHUFFLE(t0, t2, 0, 1, 4, 5);
  out[1] = SHUFFLE(t0, t2, 2, 3, 6, 7);
  out[2] = SHUFFLE(t1, t3, 0, 1, 4, 5);
  out[3] = SHUFFLE(t1, t3, 2, 3, 6, 7);
}
#undef SHUFFLE

// The 24 fields of four points (TrackPoint's order: x y z intensity, nx ny nz has_normal,
// j_photo[6], j_geo[6], inv_z2 valid pad pad).
struct Points {
  V f[24];
  V& operator[](int i) { return f[i]; }
};
Points load(const TrackPoint* const p[kLanes]) {
  Points out;
  for (int group = 0; group < 6; ++group) {
    V rows[kLanes];
    for (int l = 0; l < kLanes; ++l)
      std::memcpy(&rows[l], reinterpret_cast<const float*>(p[l]) + 4 * group, sizeof(V));
    transpose(rows[0], rows[1], rows[2], rows[3], &out.f[4 * group]);
  }
  return out;
}
enum Field { kX = 0, kY, kZ, kI, kNx, kNy, kNz, kHasNormal, kJPhoto, kJGeo = 14, kInvZ2 = 20 };

}  // namespace

NormalSums accumulate_cpu(const std::vector<TrackPoint>& points, const FrameLevel& frame,
                          const IterationParams& p) {
  NormalSums total{};
  V s[kSumCount] = {};
  const int w = frame.camera.width, h = frame.camera.height;
  const bool rolling = p.readout_rotation[0] != 0.0f || p.readout_rotation[1] != 0.0f ||
                       p.readout_rotation[2] != 0.0f;
  const std::size_t n = points.size();
  for (std::size_t i = 0, group = 0; i < n; i += kLanes, ++group) {
    if (group % kGroupsPerChunk == 0) {
      for (int k = 0; k < kSumCount; ++k) {
        total[std::size_t(k)] += double(s[k][0] + s[k][1] + s[k][2] + s[k][3]);
        s[k] = splat(0.0f);
      }
    }
    // The last group repeats the last point in the lanes past the end, masked off below.
    const TrackPoint* lane_points[kLanes];
    M present{};
    for (int l = 0; l < kLanes; ++l) {
      lane_points[l] = &points[std::min(i + std::size_t(l), n - 1)];
      present[l] = i + std::size_t(l) < n ? -1 : 0;
    }
    Points pt = load(lane_points);

    const V X0 =
        splat(p.r[0]) * pt[kX] + splat(p.r[1]) * pt[kY] + splat(p.r[2]) * pt[kZ] + splat(p.t[0]);
    const V Y0 =
        splat(p.r[3]) * pt[kX] + splat(p.r[4]) * pt[kY] + splat(p.r[5]) * pt[kZ] + splat(p.t[1]);
    const V Z0 =
        splat(p.r[6]) * pt[kX] + splat(p.r[7]) * pt[kY] + splat(p.r[8]) * pt[kZ] + splat(p.t[2]);
    M visible = present & (Z0 >= splat(p.min_depth));
    // Lanes out of play divide by 1, so that nothing below turns into inf or NaN.
    V Z = select(visible, Z0, splat(1.0f)), X = X0, Y = Y0;
    V u = splat(p.fx) * X / Z + splat(p.cx), v = splat(p.fy) * Y / Z + splat(p.cy);
    if (rolling) {  // as the reference: the row that sees the point, the point in its camera
      const V row = v / splat(float(h)) - splat(0.5f);
      const V a = -row * splat(p.readout_rotation[0]), b = -row * splat(p.readout_rotation[1]),
              c = -row * splat(p.readout_rotation[2]);
      X = X0 + (b * Z0 - c * Y0);
      Y = Y0 + (c * X0 - a * Z0);
      const V Zr = Z0 + (a * Y0 - b * X0);
      visible &= Zr >= splat(p.min_depth);
      Z = select(visible, Zr, splat(1.0f));
      u = splat(p.fx) * X / Z + splat(p.cx);
      v = splat(p.fy) * Y / Z + splat(p.cy);
    }
    visible &= (u >= splat(0.0f)) & (v >= splat(0.0f)) & (u < splat(float(w - 1))) &
               (v < splat(float(h - 1)));
    if (!(visible[0] | visible[1] | visible[2] | visible[3])) continue;

    V current{}, zc{}, ui{}, vi{};
    for (int l = 0; l < kLanes; ++l) {
      if (!visible[l]) continue;
      current[l] = bilinear(frame.intensity, u[l], v[l]);
      const int x = int(u[l] + 0.5f), y = int(v[l] + 0.5f);
      zc[l] = frame.depth_m.at(x, y);
      ui[l] = float(x);
      vi[l] = float(y);
    }
    const V in = ones(visible);
    s[kVisible] += in;

    const V rp = (current - splat(p.bias)) * splat(p.inv_gain) - pt[kI];
    const V nu = splat(p.nu);
    const V tp = in * (nu + splat(1.0f)) / (nu + rp * rp * splat(p.inv_var_photo));
    add_residual(s, &pt[kJPhoto], rp, tp * splat(p.inv_var_photo));
    s[kPhotoCount] += in;
    s[kPhotoWeightedSq] += tp * rp * rp;
    s[kPhotoSq] += in * rp * rp;
    s[kAffineW] += tp;
    s[kAffineX] += tp * pt[kI];
    s[kAffineY] += tp * current;
    s[kAffineXX] += tp * pt[kI] * pt[kI];
    s[kAffineYY] += tp * current * current;
    M inlier = visible & (magnitude(rp) <= splat(p.photo_inlier));

    // Projective association: the current frame's point at the nearest pixel.
    const M geometric = visible & (pt[kHasNormal] > splat(0.0f)) & (zc > splat(0.0f));
    if (geometric[0] | geometric[1] | geometric[2] | geometric[3]) {
      const V qx = (ui - splat(p.cx)) / splat(p.fx) * zc - X;
      const V qy = (vi - splat(p.cy)) / splat(p.fy) * zc - Y;
      const V qz = zc - Z;
      const V nx = splat(p.r[0]) * pt[kNx] + splat(p.r[1]) * pt[kNy] + splat(p.r[2]) * pt[kNz];
      const V ny = splat(p.r[3]) * pt[kNx] + splat(p.r[4]) * pt[kNy] + splat(p.r[5]) * pt[kNz];
      const V nz = splat(p.r[6]) * pt[kNx] + splat(p.r[7]) * pt[kNy] + splat(p.r[8]) * pt[kNz];
      const V g = ones(geometric);
      const V rg = g * ((nx * qx + ny * qy + nz * qz) * pt[kInvZ2]);
      const V tg = g * (nu + splat(1.0f)) / (nu + rg * rg * splat(p.inv_var_geo));
      add_residual(s, &pt[kJGeo], rg, tg * splat(p.inv_var_geo));
      s[kGeoCount] += g;
      s[kGeoWeightedSq] += tg * rg * rg;
      s[kGeoSq] += rg * rg;
      inlier &= ~geometric | (magnitude(rg) <= splat(p.geo_inlier));
    }
    s[kInliers] += ones(inlier);
  }
  for (int k = 0; k < kSumCount; ++k)
    total[std::size_t(k)] += double(s[k][0] + s[k][1] + s[k][2] + s[k][3]);
  return total;
}

}  // namespace probeless::tracking
