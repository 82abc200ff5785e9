#include "kernels/fusion/surfel_environment_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace probeless::fusion {
namespace {

// Texel index in the n x 6n layout: face f, (x, y) on it.
std::size_t texel_index(int n, int face, int x, int y) {
  return (static_cast<std::size_t>(face) * n + y) * n + x;
}

int texel_of(float uv, int n) {
  return std::clamp(static_cast<int>(std::floor(uv * static_cast<float>(n))), 0, n - 1);
}

}  // namespace

SurfelEnvironmentStats render_surfels_into_environment(const std::vector<Surfel>& surfels,
                                                       const Eigen::Vector3f& centre,
                                                       envmap::ImageRGBAF& texels,
                                                       const SurfelEnvironmentOptions& o) {
  const int n = envmap::face_size_of(texels);
  if (n < 1 || texels.height() != 6 * n)
    throw std::invalid_argument("render_surfels_into_environment: texels are not n x 6n");
  if (!(o.min_distance_m > 0) || !(o.max_distance_m > o.min_distance_m) || !(o.max_splat_rad > 0) ||
      !(o.max_splat_rad < 1.5f))
    throw std::invalid_argument("render_surfels_into_environment: options out of range");

  const std::size_t count = static_cast<std::size_t>(6) * n * n;
  // The nearest surfel per texel: its distance (inf: none) and index.
  std::vector<float> depth(count, std::numeric_limits<float>::infinity());
  std::vector<std::uint32_t> nearest(count, 0);
  SurfelEnvironmentStats stats;

  for (std::size_t i = 0; i < surfels.size(); ++i) {
    const Surfel& s = surfels[i];
    const Eigen::Vector3f d = s.position - centre;
    const float dist = d.norm();
    if (!std::isfinite(dist) || dist < o.min_distance_m || dist > o.max_distance_m) continue;
    ++stats.surfels_drawn;
    const Eigen::Vector3f dir = d / dist;
    const float alpha = std::min(std::atan(std::max(s.radius, 0.0f) / dist), o.max_splat_rad);
    const float cos_alpha = std::cos(alpha);
    const envmap::CubeCoord c = envmap::cube_coord_of(dir);
    const int cx = texel_of(c.u, n), cy = texel_of(c.v, n);
    // The cone's footprint on the face plane (at distance 1 along the major axis): an angle a
    // at a plane point at distance L from the centre moves it by up to L^2 a (L^2 = 1 + sc^2 +
    // tc^2, the stretch towards a face's corners), so the window is that in texels, plus one.
    const float sc = 2.0f * c.u - 1.0f, tc = 2.0f * c.v - 1.0f;
    const float half_plane = std::tan(alpha) * (1.0f + sc * sc + tc * tc);
    const int half = std::min(static_cast<int>(std::ceil(half_plane * 0.5f * n)) + 1, n);
    for (int y = cy - half; y <= cy + half; ++y)
      for (int x = cx - half; x <= cx + half; ++x) {
        // The texel's direction, its face's plane extended past the edge when (x, y) is off
        // the face, so that a splat over an edge lands on the neighbouring face's texels.
        Eigen::Vector3f td = envmap::cube_face_direction(c.face, (static_cast<float>(x) + 0.5f) / n,
                                                         (static_cast<float>(y) + 0.5f) / n);
        td.normalize();
        const bool centre_texel = x == cx && y == cy;
        if (!centre_texel && td.dot(dir) < cos_alpha) continue;
        int face = c.face, tx = x, ty = y;
        if (x < 0 || y < 0 || x >= n || y >= n) {
          const envmap::CubeCoord t = envmap::cube_coord_of(td);
          face = t.face;
          tx = texel_of(t.u, n);
          ty = texel_of(t.v, n);
        }
        const std::size_t k = texel_index(n, face, tx, ty);
        if (dist < depth[k]) {
          depth[k] = dist;
          nearest[k] = static_cast<std::uint32_t>(i);
        }
      }
  }

  std::vector<std::uint8_t> covered(count, 0);
  for (std::size_t k = 0; k < count; ++k) covered[k] = std::isfinite(depth[k]) ? 1 : 0;
  const auto write = [&](std::size_t k, std::uint32_t surfel) {
    const int face = static_cast<int>(k / (static_cast<std::size_t>(n) * n));
    const int rest = static_cast<int>(k % (static_cast<std::size_t>(n) * n));
    const int x = rest % n, y = face * n + rest / n;
    for (int ch = 0; ch < 3; ++ch) texels.at(x, y, ch) = surfels[surfel].radiance[ch];
    texels.at(x, y, 3) = 1.0f;
  };

  if (o.gap_fill) {
    // Dilate: an uncovered texel with a covered 8-neighbour takes the nearest one's surfel.
    std::vector<std::uint8_t> dilated = covered;
    std::vector<std::uint32_t> fill(count, 0);
    for (int f = 0; f < 6; ++f)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const std::size_t k = texel_index(n, f, x, y);
          if (covered[k]) continue;
          float best = std::numeric_limits<float>::infinity();
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int xx = x + dx, yy = y + dy;
              if (xx < 0 || yy < 0 || xx >= n || yy >= n) continue;
              const std::size_t kk = texel_index(n, f, xx, yy);
              if (covered[kk] && depth[kk] < best) {
                best = depth[kk];
                fill[k] = nearest[kk];
                dilated[k] = 1;
              }
            }
        }
    // Erode: a dilated texel stays only if all its 8 neighbours are in the dilated set (the
    // covered ones stay whatever their neighbours: the closing keeps what was covered).
    for (int f = 0; f < 6; ++f)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const std::size_t k = texel_index(n, f, x, y);
          if (covered[k] || !dilated[k]) continue;
          bool inside = true;
          for (int dy = -1; dy <= 1 && inside; ++dy)
            for (int dx = -1; dx <= 1 && inside; ++dx) {
              const int xx = x + dx, yy = y + dy;
              inside =
                  xx >= 0 && yy >= 0 && xx < n && yy < n && dilated[texel_index(n, f, xx, yy)] != 0;
            }
          if (!inside) continue;
          write(k, fill[k]);
          ++stats.texels_filled;
        }
  }
  for (std::size_t k = 0; k < count; ++k)
    if (covered[k]) {
      write(k, nearest[k]);
      ++stats.texels_covered;
    }
  return stats;
}

}  // namespace probeless::fusion
