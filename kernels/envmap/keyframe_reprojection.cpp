#include "kernels/envmap/keyframe_reprojection.hpp"

#include <algorithm>
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

ImageRGBAF reproject_keyframe(const ImageRGBAF& texels, const Eigen::Vector3d& keyframe_position,
                              const std::optional<RoomBox>& room, const Eigen::Vector3d& target,
                              int m, int samples) {
  const int n = face_size_of(texels);
  if (texels.height() != 6 * n || m < 1 || samples < 1)
    throw std::invalid_argument("reproject_keyframe: bad sizes");
  const ParallaxConstants p = reprojection_constants(room, keyframe_position, target);
  const float inv = 1.0F / static_cast<float>(m * samples);
  ImageRGBAF out = make_texels(m);
  for (int row = 0; row < 6 * m; ++row) {
    const int face = row / m, y = row - face * m;
    for (int x = 0; x < m; ++x) {
      float sum[3] = {0, 0, 0};
      bool all = true;
      for (int j = 0; j < samples; ++j)
        for (int i = 0; i < samples; ++i) {
          const float u = (static_cast<float>(x * samples + i) + 0.5F) * inv;
          const float v = (static_cast<float>(y * samples + j) + 0.5F) * inv;
          const Eigen::Vector3f w = parallax_direction(p, cube_face_direction(face, u, v));
          const CubeCoord cc = cube_coord_of(w);
          const float px = cc.u * static_cast<float>(n) - 0.5F;
          const float py = cc.v * static_cast<float>(n) - 0.5F;
          const float x0f = std::floor(px), y0f = std::floor(py);
          const float ax = px - x0f, ay = py - y0f;
          const auto at = [&](float xf, float yf) {
            const int xi = std::clamp(static_cast<int>(xf), 0, n - 1);
            const int yi = std::clamp(static_cast<int>(yf), 0, n - 1);
            return &texels.at(xi, cc.face * n + yi, 0);
          };
          const float *a = at(x0f, y0f), *b = at(x0f + 1.0F, y0f), *c = at(x0f, y0f + 1.0F),
                      *e = at(x0f + 1.0F, y0f + 1.0F);
          for (int ch = 0; ch < 3; ++ch) {
            const float dab = b[ch] - a[ch], dce = e[ch] - c[ch];
            const float top = a[ch] + ax * dab, bottom = c[ch] + ax * dce;
            const float dv = bottom - top;
            sum[ch] += top + ay * dv;
          }
          all = all && a[3] > 0.0F && (ax == 0.0F || b[3] > 0.0F) && (ay == 0.0F || c[3] > 0.0F) &&
                (ax == 0.0F || ay == 0.0F || e[3] > 0.0F);
        }
      const float count = static_cast<float>(samples * samples);
      for (int c = 0; c < 3; ++c) out.at(x, row, c) = sum[c] / count;
      out.at(x, row, 3) = all ? 1.0F : 0.0F;
    }
  }
  return out;
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
