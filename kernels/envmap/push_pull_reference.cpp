#include "kernels/envmap/push_pull_reference.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/envmap/push_pull.hpp"

namespace probeless::envmap {

namespace {

float level_weight(const float* t, bool is_texels) {
  return is_texels ? (t[3] != 0.0F ? 1.0F : 0.0F) : t[3];
}

void pull(const ImageRGBAF& fine, bool fine_is_texels, ImageRGBAF& coarse, int mask) {
  const int fs = fine.width(), cs = coarse.width();
  for (int row = 0; row < 6 * cs; ++row) {
    const int face = row / cs, y = row - face * cs;
    if (!(mask >> face & 1)) continue;
    for (int x = 0; x < cs; ++x) {
      float sum[3] = {0, 0, 0}, wsum = 0;
      for (int j = 0; j < 2 && 2 * y + j < fs; ++j)
        for (int i = 0; i < 2 && 2 * x + i < fs; ++i) {
          const float* t = &fine.at(2 * x + i, face * fs + 2 * y + j);
          const float w = level_weight(t, fine_is_texels);
          for (int c = 0; c < 3; ++c) sum[c] += w * t[c];
          wsum += w;
        }
      float* out = &coarse.at(x, row);
      for (int c = 0; c < 3; ++c) out[c] = wsum > 0 ? sum[c] / wsum : 0.0F;
      out[3] = wsum > 0 ? std::min(wsum, 1.0F) : 0.0F;
    }
  }
}

void push(ImageRGBAF& fine, bool fine_is_texels, const ImageRGBAF& coarse, int mask) {
  const int fs = fine.width(), cs = coarse.width();
  for (int row = 0; row < 6 * fs; ++row) {
    const int face = row / fs, y = row - face * fs;
    if (!(mask >> face & 1)) continue;
    for (int x = 0; x < fs; ++x) {
      float* t = &fine.at(x, row);
      const float* p = &coarse.at(x / 2, face * cs + y / 2);
      if (fine_is_texels) {
        if (t[3] == 0.0F) {
          for (int c = 0; c < 3; ++c) t[c] = p[c];
        } else if (t[3] < 0.0F) {
          t[3] = 0.0F;
        }
      } else if (t[3] < 1.0F) {
        for (int c = 0; c < 3; ++c) t[c] = t[3] * t[c] + (1.0F - t[3]) * p[c];
        t[3] = 1.0F;
      }
    }
  }
}

void pull_push(ImageRGBAF& texels, std::vector<ImageRGBAF>& levels, int mask) {
  for (std::size_t k = 0; k < levels.size(); ++k)
    pull(k == 0 ? texels : levels[k - 1], k == 0, levels[k], mask);
  for (std::size_t k = levels.size(); k-- > 0;)
    push(k == 0 ? texels : levels[k - 1], k == 0, levels[k], mask);
}

void seed_borders(ImageRGBAF& texels, int empty_mask, int source_mask) {
  const int n = texels.width();
  const float inv_n = 1.0F / static_cast<float>(n);
  for (int face = 0; face < 6; ++face) {
    if (!(empty_mask >> face & 1)) continue;
    for (int edge = 0; edge < 4; ++edge)
      for (int i = 0; i < n; ++i) {
        int x, y;
        float du = 0, dv = 0;
        if (edge < 2) {
          x = i;
          y = edge == 0 ? 0 : n - 1;
          dv = edge == 0 ? -1.0F : 1.0F;
        } else {
          if (i == 0 || i == n - 1) continue;
          y = i;
          x = edge == 2 ? 0 : n - 1;
          du = edge == 2 ? -1.0F : 1.0F;
        }
        const Eigen::Vector3f d =
            cube_face_direction(face, (static_cast<float>(x) + 0.5F + du) * inv_n,
                                (static_cast<float>(y) + 0.5F + dv) * inv_n);
        const CubeTexel ct = cube_texel_from_direction(d.cast<double>());
        const int source = static_cast<int>(ct.face);
        if (source == face || !(source_mask >> source & 1)) continue;
        const int sx = std::clamp(static_cast<int>(ct.u * n), 0, n - 1);
        const int sy = std::clamp(static_cast<int>(ct.v * n), 0, n - 1);
        float* t = &texels.at(x, face * n + y);
        for (int c = 0; c < 3; ++c) t[c] = texels.at(sx, source * n + sy, c);
        t[3] = -1.0F;
      }
  }
}

}  // namespace

int push_pull_reference(ImageRGBAF& texels) {
  const int n = texels.width();
  if (n <= 1) return 0;
  std::vector<ImageRGBAF> levels;
  for (int m = n; m > 1;) {
    m = (m + 1) / 2;
    levels.emplace_back(m, 6 * m);
  }
  pull_push(texels, levels, 0x3F);
  int have = 0;
  for (int f = 0; f < 6; ++f)
    if (levels.back().at(0, f, 3) > 0) have |= 1 << f;
  const int observed = have;
  for (int pass = 0; pass < 3 && have != 0 && have != 0x3F; ++pass) {
    int reachable = 0;
    for (int f = 0; f < 6; ++f)
      if (!(have >> f & 1) && (adjacent_faces(f) & have)) reachable |= 1 << f;
    seed_borders(texels, reachable, have);
    pull_push(texels, levels, reachable);
    have |= reachable;
  }
  return observed;
}

}  // namespace probeless::envmap
