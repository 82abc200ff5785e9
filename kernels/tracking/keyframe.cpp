#include "kernels/tracking/keyframe.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace probeless::tracking {
namespace {

// Neighbours farther apart in depth than this fraction are on different surfaces: no normal.
constexpr float kNormalMaxDepthStep = 0.1f;
// Normals seen nearly edge-on (|cos| below this) are too noisy for point-to-plane.
constexpr float kNormalMinCos = 0.2f;

Eigen::Vector3f backproject(const LevelCamera& c, float x, float y, float z) {
  return {(x - c.cx) / c.fx * z, (y - c.cy) / c.fy * z, z};
}

bool normal_at(const FrameLevel& f, int x, int y, Eigen::Vector3f& n) {
  const float z = f.depth_m.at(x, y);
  const float zl = f.depth_m.at(x - 1, y), zr = f.depth_m.at(x + 1, y);
  const float zu = f.depth_m.at(x, y - 1), zd = f.depth_m.at(x, y + 1);
  const float step = kNormalMaxDepthStep * z;
  for (const float zn : {zl, zr, zu, zd})
    if (!(zn > 0.0f) || std::abs(zn - z) > step) return false;
  const auto& c = f.camera;
  const Eigen::Vector3f dx =
      backproject(c, float(x + 1), float(y), zr) - backproject(c, float(x - 1), float(y), zl);
  const Eigen::Vector3f dy =
      backproject(c, float(x), float(y + 1), zd) - backproject(c, float(x), float(y - 1), zu);
  n = dx.cross(dy);
  const float len = n.norm();
  if (!(len > 0.0f)) return false;
  n /= len;
  const Eigen::Vector3f p = backproject(c, float(x), float(y), z);
  const float cosine = n.dot(p) / p.norm();
  if (cosine > 0.0f) n = -n;
  return std::abs(cosine) >= kNormalMinCos;
}

TrackPoint make_point(const FrameLevel& f, int x, int y, float gx, float gy) {
  const auto& c = f.camera;
  const float z = f.depth_m.at(x, y);
  const Eigen::Vector3f p = backproject(c, float(x), float(y), z);
  TrackPoint t{};
  t.x = p.x();
  t.y = p.y();
  t.z = p.z();
  t.intensity = f.intensity.at(x, y);
  // Photometric: grad I * d pi / dP * [I | -[P]x]; the rotational part is P x (translational).
  const Eigen::Vector3f jt(gx * c.fx / z, gy * c.fy / z, 0.0f);
  const Eigen::Vector3f jv(jt.x(), jt.y(), -(jt.x() * p.x() + jt.y() * p.y()) / z);
  const Eigen::Vector3f jw = p.cross(jv);
  for (int i = 0; i < 3; ++i) {
    t.j_photo[i] = jv[i];
    t.j_photo[3 + i] = jw[i];
  }
  t.inv_z2 = 1.0f / (z * z);
  t.valid = 1.0f;
  Eigen::Vector3f n;
  if (normal_at(f, x, y, n)) {
    t.nx = n.x();
    t.ny = n.y();
    t.nz = n.z();
    t.has_normal = 1.0f;
    const Eigen::Vector3f pn = p.cross(n);
    for (int i = 0; i < 3; ++i) {
      t.j_geo[i] = -n[i] * t.inv_z2;
      t.j_geo[3 + i] = -pn[i] * t.inv_z2;
    }
  }
  return t;
}

// One point per block: the largest intensity gradient among pixels with depth (DSO's
// selection, Engel et al. 2018, keeps points spread over the image and on texture).
std::vector<TrackPoint> select_points(const FrameLevel& f, int max_points) {
  const int w = f.camera.width, h = f.camera.height;
  std::vector<TrackPoint> points;
  if (w < 3 || h < 3) return points;
  const int block = point_block_size(w, h, max_points);
  points.reserve(std::size_t((w / block + 1) * (h / block + 1)));
  for (int by = 1; by < h - 1; by += block)
    for (int bx = 1; bx < w - 1; bx += block) {
      int best_x = -1, best_y = -1;
      float best_g2 = -1.0f, best_gx = 0, best_gy = 0;
      for (int y = by; y < std::min(by + block, h - 1); ++y)
        for (int x = bx; x < std::min(bx + block, w - 1); ++x) {
          if (!(f.depth_m.at(x, y) > 0.0f)) continue;
          const float gx = 0.5f * (f.intensity.at(x + 1, y) - f.intensity.at(x - 1, y));
          const float gy = 0.5f * (f.intensity.at(x, y + 1) - f.intensity.at(x, y - 1));
          const float g2 = gx * gx + gy * gy;
          if (g2 > best_g2) {
            best_g2 = g2;
            best_x = x;
            best_y = y;
            best_gx = gx;
            best_gy = gy;
          }
        }
      if (best_x >= 0) points.push_back(make_point(f, best_x, best_y, best_gx, best_gy));
    }
  return points;
}

}  // namespace

int point_block_size(int width, int height, int max_points) {
  // At least 2x2 blocks: coarse levels only start the finer ones, they need no more points.
  return std::max(
      2, int(std::ceil(std::sqrt(double(width) * height / double(std::max(1, max_points))))));
}

Keyframe make_keyframe(const FramePyramid& pyramid, const Pose& T_world_keyframe,
                       int max_points_per_level, const std::array<float, 3>& readout_rotation) {
  Keyframe k;
  k.T_world_keyframe = T_world_keyframe;
  for (const auto& level : pyramid.levels) {
    k.cameras.push_back(level.camera);
    k.points.push_back(select_points(level, max_points_per_level));
  }
  undo_rolling_shutter(k, readout_rotation);
  return k;
}

void undo_rolling_shutter(Keyframe& keyframe, const std::array<float, 3>& readout_rotation) {
  if (readout_rotation == std::array<float, 3>{}) return;
  const auto rotate = [](float a, float b, float c, float& x, float& y, float& z) {
    const float x0 = x, y0 = y, z0 = z;
    x = x0 + (b * z0 - c * y0);
    y = y0 + (c * x0 - a * z0);
    z = z0 + (a * y0 - b * x0);
  };
  for (std::size_t l = 0; l < keyframe.points.size(); ++l) {
    const LevelCamera& c = keyframe.cameras[l];
    for (TrackPoint& p : keyframe.points[l]) {
      const float s = (c.fy * p.y / p.z + c.cy) / float(c.height) - 0.5f;
      const float a = s * readout_rotation[0], b = s * readout_rotation[1],
                  g = s * readout_rotation[2];
      rotate(a, b, g, p.x, p.y, p.z);
      if (p.has_normal > 0.0f) rotate(a, b, g, p.nx, p.ny, p.nz);
    }
  }
}

}  // namespace probeless::tracking
