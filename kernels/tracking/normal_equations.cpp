#include "kernels/tracking/normal_equations.hpp"

#include <cmath>

#include "kernels/tracking/normal_equations_terms.hpp"

namespace probeless::tracking {
namespace {

using detail::add_residual;
using detail::bilinear;

// Points are summed in float in chunks as the device's work-items do, the chunks in double.
constexpr std::size_t kChunk = 64;

}  // namespace

NormalSums accumulate_reference(const std::vector<TrackPoint>& points, const FrameLevel& frame,
                                const IterationParams& p) {
  NormalSums total{};
  float s[kSumCount] = {};
  const int w = frame.camera.width, h = frame.camera.height;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i % kChunk == 0) {
      for (int k = 0; k < kSumCount; ++k) {
        total[std::size_t(k)] += double(s[k]);
        s[k] = 0.0f;
      }
    }
    const TrackPoint& pt = points[i];
    const float X0 = p.r[0] * pt.x + p.r[1] * pt.y + p.r[2] * pt.z + p.t[0];
    const float Y0 = p.r[3] * pt.x + p.r[4] * pt.y + p.r[5] * pt.z + p.t[1];
    const float Z0 = p.r[6] * pt.x + p.r[7] * pt.y + p.r[8] * pt.z + p.t[2];
    if (!(Z0 >= p.min_depth)) continue;
    float u = p.fx * X0 / Z0 + p.cx, v = p.fy * Y0 / Z0 + p.cy;
    float X = X0, Y = Y0, Z = Z0;
    if (p.readout_rotation[0] != 0.0f || p.readout_rotation[1] != 0.0f ||
        p.readout_rotation[2] != 0.0f) {
      // Rolling shutter: the row that sees the point was exposed `row` of the readout after
      // the middle row, when the camera had turned by row * readout_rotation: the point in that
      // row's camera (small angle), projected again; the row is the first projection's.
      const float row = v / float(h) - 0.5f;
      const float a = -row * p.readout_rotation[0], b = -row * p.readout_rotation[1],
                  c = -row * p.readout_rotation[2];
      X = X0 + (b * Z0 - c * Y0);
      Y = Y0 + (c * X0 - a * Z0);
      Z = Z0 + (a * Y0 - b * X0);
      if (!(Z >= p.min_depth)) continue;
      u = p.fx * X / Z + p.cx;
      v = p.fy * Y / Z + p.cy;
    }
    if (!(u >= 0.0f && v >= 0.0f && u < float(w - 1) && v < float(h - 1))) continue;
    s[kVisible] += 1.0f;
    bool inlier = true;

    const float current = bilinear(frame.intensity, u, v);
    const float rp = (current - p.bias) * p.inv_gain - pt.intensity;
    const float tp = (p.nu + 1.0f) / (p.nu + rp * rp * p.inv_var_photo);
    add_residual(s, pt.j_photo, rp, tp * p.inv_var_photo);
    s[kPhotoCount] += 1.0f;
    s[kPhotoWeightedSq] += tp * rp * rp;
    s[kPhotoSq] += rp * rp;
    s[kAffineW] += tp;
    s[kAffineX] += tp * pt.intensity;
    s[kAffineY] += tp * current;
    s[kAffineXX] += tp * pt.intensity * pt.intensity;
    s[kAffineYY] += tp * current * current;
    inlier = std::abs(rp) <= p.photo_inlier;

    if (pt.has_normal > 0.0f) {
      // Projective association: the current frame's point at the nearest pixel.
      const int ui = int(u + 0.5f), vi = int(v + 0.5f);
      const float zc = frame.depth_m.at(ui, vi);
      if (zc > 0.0f) {
        const float qx = (float(ui) - p.cx) / p.fx * zc - X;
        const float qy = (float(vi) - p.cy) / p.fy * zc - Y;
        const float qz = zc - Z;
        const float nx = p.r[0] * pt.nx + p.r[1] * pt.ny + p.r[2] * pt.nz;
        const float ny = p.r[3] * pt.nx + p.r[4] * pt.ny + p.r[5] * pt.nz;
        const float nz = p.r[6] * pt.nx + p.r[7] * pt.ny + p.r[8] * pt.nz;
        const float rg = (nx * qx + ny * qy + nz * qz) * pt.inv_z2;
        const float tg = (p.nu + 1.0f) / (p.nu + rg * rg * p.inv_var_geo);
        add_residual(s, pt.j_geo, rg, tg * p.inv_var_geo);
        s[kGeoCount] += 1.0f;
        s[kGeoWeightedSq] += tg * rg * rg;
        s[kGeoSq] += rg * rg;
        inlier = inlier && std::abs(rg) <= p.geo_inlier;
      }
    }
    if (inlier) s[kInliers] += 1.0f;
  }
  for (int k = 0; k < kSumCount; ++k) total[std::size_t(k)] += double(s[k]);
  return total;
}

}  // namespace probeless::tracking
