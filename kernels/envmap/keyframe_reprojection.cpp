#include "kernels/envmap/keyframe_reprojection.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace probeless::envmap {

ParallaxConstants reprojection_constants(const std::optional<RoomBox>& room,
                                         const Eigen::Vector3d& keyframe_position,
                                         const Eigen::Vector3d& target) {
  ParallaxConstants c;
  if (!room || !inside(*room, keyframe_position) || !inside(*room, target)) return c;
  c.enabled = true;
  c.lo = (room->lo - target).cast<float>();
  c.hi = (room->hi - target).cast<float>();
  c.offset = (target - keyframe_position).cast<float>();
  return c;
}

namespace {

// Catmull-Rom weights of the taps at -1, 0, 1, 2 for a sample at t in [0, 1) past tap 0.
std::array<float, 4> catmull_rom(float t) {
  const float t2 = t * t, t3 = t2 * t;
  return {0.5F * (-t3 + 2 * t2 - t), 0.5F * (3 * t3 - 5 * t2 + 2), 0.5F * (-3 * t3 + 4 * t2 + t),
          0.5F * (t3 - t2)};
}

using Texel = Eigen::Array4f;

}  // namespace

ReprojectionMap::ReprojectionMap(int n, const Eigen::Vector3d& keyframe_position,
                                 const std::optional<RoomBox>& room, const Eigen::Vector3d& target,
                                 int m, int samples)
    : n_(n), m_(m), samples_(samples) {
  if (n < 1 || m < 1 || samples < 1) throw std::invalid_argument("reproject_keyframe: bad sizes");
  const ParallaxConstants p = reprojection_constants(room, keyframe_position, target);
  const float inv = 1.0F / static_cast<float>(m * samples);
  taps_.reserve(static_cast<std::size_t>(6 * m * m * samples * samples));
  for (int row = 0; row < 6 * m; ++row) {
    const int face = row / m, y = row - face * m;
    for (int x = 0; x < m; ++x)
      for (int j = 0; j < samples; ++j)
        for (int i = 0; i < samples; ++i) {
          const float u = (static_cast<float>(x * samples + i) + 0.5F) * inv;
          const float v = (static_cast<float>(y * samples + j) + 0.5F) * inv;
          const CubeCoord cc =
              cube_coord_of(parallax_direction(p, cube_face_direction(face, u, v)));
          // Texel centres on integers.
          const float px = cc.u * static_cast<float>(n) - 0.5F;
          const float py = cc.v * static_cast<float>(n) - 0.5F;
          const float x0 = std::floor(px), y0 = std::floor(py);
          taps_.push_back({cc.face, static_cast<int>(x0), static_cast<int>(y0), px - x0, py - y0});
        }
  }
}

ImageRGBAF ReprojectionMap::apply(const ImageRGBAF& texels, Resampling resampling) const {
  if (face_size_of(texels) != n_ || texels.height() != 6 * n_)
    throw std::invalid_argument("reproject_keyframe: the keyframe is not the map's size");
  ImageRGBAF out = make_texels(m_);
  const float* base = &texels.at(0, 0, 0);
  const auto at = [&](int face, int x, int y) {
    const int xi = std::clamp(x, 0, n_ - 1), yi = std::clamp(y, 0, n_ - 1);
    return Eigen::Map<const Texel>(base + 4 * ((face * n_ + yi) * n_ + xi));
  };
  const float count = static_cast<float>(samples_ * samples_);
  auto tap = taps_.begin();
  for (int row = 0; row < 6 * m_; ++row)
    for (int x = 0; x < m_; ++x) {
      Texel sum = Texel::Zero();
      bool all = true;
      for (int s = 0; s < samples_ * samples_; ++s, ++tap) {
        const Tap& t = *tap;
        const Texel a = at(t.face, t.x0, t.y0), b = at(t.face, t.x0 + 1, t.y0);
        const Texel c = at(t.face, t.x0, t.y0 + 1), d = at(t.face, t.x0 + 1, t.y0 + 1);
        if (resampling == Resampling::Bilinear) {
          const Texel top = a + t.ax * (b - a), bottom = c + t.ax * (d - c);
          sum += top + t.ay * (bottom - top);
        } else {
          const std::array<float, 4> wx = catmull_rom(t.ax), wy = catmull_rom(t.ay);
          Texel v = Texel::Zero();
          for (int j = 0; j < 4; ++j) {
            Texel line = Texel::Zero();
            for (int i = 0; i < 4; ++i) line += wx[i] * at(t.face, t.x0 - 1 + i, t.y0 - 1 + j);
            v += wy[j] * line;
          }
          // Within the bilinear footprint's range: no ringing around a lamp (radiance < 0 or
          // a halo brighter than the lamp).
          sum += v.max(a.min(b).min(c.min(d))).min(a.max(b).max(c.max(d)));
        }
        all = all && a[3] > 0.0F && (t.ax == 0.0F || b[3] > 0.0F) &&
              (t.ay == 0.0F || c[3] > 0.0F) && (t.ax == 0.0F || t.ay == 0.0F || d[3] > 0.0F);
      }
      float* o = &out.at(x, row, 0);
      for (int ch = 0; ch < 3; ++ch) o[ch] = sum[ch] / count;
      o[3] = all ? 1.0F : 0.0F;
    }
  return out;
}

ImageRGBAF reproject_keyframe(const ImageRGBAF& texels, const Eigen::Vector3d& keyframe_position,
                              const std::optional<RoomBox>& room, const Eigen::Vector3d& target,
                              int m, int samples, Resampling resampling) {
  const int n = face_size_of(texels);
  if (texels.height() != 6 * n) throw std::invalid_argument("reproject_keyframe: bad sizes");
  return ReprojectionMap(n, keyframe_position, room, target, m, samples).apply(texels, resampling);
}

int fill_unobserved(ImageRGBAF& target, const std::vector<const ImageRGBAF*>& others) {
  for (const ImageRGBAF* o : others)
    if (o->width() != target.width() || o->height() != target.height())
      throw std::invalid_argument("fill_unobserved: the environments' sizes differ");
  int filled = 0;
  for (int y = 0; y < target.height(); ++y)
    for (int x = 0; x < target.width(); ++x) {
      float* t = &target.at(x, y, 0);
      if (t[3] > 0.0F) continue;
      float sum[3] = {0, 0, 0};
      int count = 0;
      for (const ImageRGBAF* o : others) {
        const float* s = &o->at(x, y, 0);
        if (!(s[3] > 0.0F)) continue;
        for (int c = 0; c < 3; ++c) sum[c] += s[c];
        ++count;
      }
      if (count == 0) continue;
      for (int c = 0; c < 3; ++c) t[c] = sum[c] / static_cast<float>(count);
      t[3] = 1.0F;
      ++filled;
    }
  return filled;
}

}  // namespace probeless::envmap
