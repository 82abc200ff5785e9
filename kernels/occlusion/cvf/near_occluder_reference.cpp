#include "kernels/occlusion/cvf/near_occluder_reference.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kernels/occlusion/common/cvf_params.hpp"

namespace probeless::occlusion {

NearOccluderParams near_occluder_params(const CvfLocalParams& params) {
  NearOccluderParams p;
  p.depth_tolerance_mm = params.cvf.categorise.depth_tolerance_mm;
  p.min_samples = params.cvf.min_samples;
  p.tile_px = std::max(1, params.tile_px);
  p.prior_radius = params.prior_radius;
  return p;
}

HoleColourModels hole_colour_models(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                                    const ImageF& virtual_depth_mm, const NearOccluderParams& p) {
  const int w = colour.width(), h = colour.height();
  if (real_depth_mm.width() != w || real_depth_mm.height() != h || virtual_depth_mm.width() != w ||
      virtual_depth_mm.height() != h)
    throw std::invalid_argument("near occluder: colour, real and virtual depth sizes differ");
  const int bins = p.bins_per_channel * p.bins_per_channel * p.bins_per_channel;
  HoleColourModels m;
  m.hole.assign(bins, 0);
  m.behind.assign(bins, 0);
  m.tiles_x = (w + p.tile_px - 1) / p.tile_px;
  m.tiles_y = (h + p.tile_px - 1) / p.tile_px;
  m.tile_behind.assign(std::size_t(m.tiles_x) * m.tiles_y * bins, 0);
  m.tile_behind_total.assign(std::size_t(m.tiles_x) * m.tiles_y, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = virtual_depth_mm.at(x, y);
      if (!(v > 0.0F)) continue;
      const std::uint16_t r = real_depth_mm.at(x, y);
      const int b = colour_bin(colour.at(x, y, 0), colour.at(x, y, 1), colour.at(x, y, 2),
                               p.bins_per_channel);
      if (r == 0) {
        ++m.hole[b];
        ++m.hole_total;
      } else if (static_cast<float>(r) - v > p.depth_tolerance_mm) {
        ++m.behind[b];
        ++m.behind_total;
        const int t = (y / p.tile_px) * m.tiles_x + x / p.tile_px;
        ++m.tile_behind[std::size_t(t) * bins + b];
        ++m.tile_behind_total[t];
      }
    }
  return m;
}

float background_explains(const HoleColourModels& m, const NearOccluderParams& p, int x, int y,
                          int b) {
  const auto min = std::uint32_t(std::max(1, p.min_samples));
  if (m.hole_total < min || m.behind_total < min) return 1.0F;
  // In float, in the order of near_occluder.cl.
  const int bins = int(m.hole.size());
  const float nbins = float(bins);
  const float p_global = (float(m.behind[b]) + 1.0F) / (float(m.behind_total) + nbins);
  const int tx = x / p.tile_px, ty = y / p.tile_px;
  float n = 0.0F, total = 0.0F;
  for (int j = std::max(0, ty - 1); j <= std::min(m.tiles_y - 1, ty + 1); ++j)
    for (int i = std::max(0, tx - 1); i <= std::min(m.tiles_x - 1, tx + 1); ++i) {
      const int t = j * m.tiles_x + i;
      n += float(m.tile_behind[std::size_t(t) * bins + b]);
      total += float(m.tile_behind_total[t]);
    }
  const float shrink = float(min);
  const float p_behind = (n + shrink * p_global) / (total + shrink);
  const float p_hole = (float(m.hole[b]) + 1.0F) / (float(m.hole_total) + nbins);
  return std::min(1.0F, p_behind / p_hole);
}

void apply_near_occluder_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                                   const ImageF& virtual_depth_mm, const NearOccluderParams& p,
                                   ImageF& alpha) {
  const auto m = hole_colour_models(colour, real_depth_mm, virtual_depth_mm, p);
  const int w = colour.width(), h = colour.height();
  ImageF q(w, h);  // 1 on known depth, -1 off the object
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float v = -1.0F;
      if (virtual_depth_mm.at(x, y) > 0.0F) {
        v = 1.0F;
        if (real_depth_mm.at(x, y) == 0)
          v = background_explains(m, p, x, y,
                                  colour_bin(colour.at(x, y, 0), colour.at(x, y, 1),
                                             colour.at(x, y, 2), p.bins_per_channel));
      }
      q.at(x, y) = v;
    }
  const int r = std::max(0, p.prior_radius);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float qc = q.at(x, y);
      if (qc < 0.0F || real_depth_mm.at(x, y) != 0 || qc >= 1.0F) continue;
      float near = 0.0F, n = 0.0F;
      for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy)
        for (int xx = std::max(0, x - r); xx <= std::min(w - 1, x + r); ++xx) {
          const float v = q.at(xx, yy);
          if (v < 0.0F) continue;
          near += 1.0F - v;
          n += 1.0F;
        }
      const float mean = (near + 1.0F) / (n + 2.0F);
      const float keep = qc * (1.0F - mean);
      const float cap = keep / (keep + (1.0F - qc) * mean);
      alpha.at(x, y) = std::min(alpha.at(x, y), cap);
    }
}

}  // namespace probeless::occlusion
