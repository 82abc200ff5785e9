#include "kernels/occlusion/cvf/cvf_local_reference.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kernels/occlusion/common/categorise_reference.hpp"
#include "kernels/occlusion/common/guided_filter_reference.hpp"
#include "kernels/occlusion/cvf/cvf_reference.hpp"
#include "kernels/occlusion/cvf/hole_core_reference.hpp"
#include "kernels/occlusion/cvf/near_occluder_reference.hpp"

namespace probeless::occlusion {

TileColourModels tile_histograms_reference(const ImageRGB8& colour, const CategoryImage& categories,
                                           const ImageGray8& band, int bins_per_channel,
                                           int tile_px) {
  if (bins_per_channel < 1 || bins_per_channel > 16)
    throw std::invalid_argument("tile histograms: bins per channel must be 1..16");
  if (tile_px < 1) throw std::invalid_argument("tile histograms: tile size must be positive");
  TileColourModels t;
  t.tile_px = tile_px;
  t.bins_per_channel = bins_per_channel;
  t.tiles_x = std::max(1, (colour.width() + tile_px - 1) / tile_px);
  t.tiles_y = std::max(1, (colour.height() + tile_px - 1) / tile_px);
  const auto n = static_cast<std::size_t>(t.tiles()) * t.bins();
  t.infront.assign(n, 0);
  t.behind.assign(n, 0);
  t.infront_total.assign(t.tiles(), 0);
  t.behind_total.assign(t.tiles(), 0);
  for (int y = 0; y < colour.height(); ++y)
    for (int x = 0; x < colour.width(); ++x) {
      if (!band.at(x, y)) continue;
      const auto c = static_cast<Category>(categories.at(x, y));
      if (c != Category::Infront && c != Category::Behind) continue;
      const int tile = (y / tile_px) * t.tiles_x + x / tile_px;
      const int bin =
          colour_bin(colour.at(x, y, 0), colour.at(x, y, 1), colour.at(x, y, 2), bins_per_channel);
      const auto idx = static_cast<std::size_t>(tile) * t.bins() + bin;
      if (c == Category::Infront) {
        t.infront[idx]++;
        t.infront_total[tile]++;
      } else {
        t.behind[idx]++;
        t.behind_total[tile]++;
      }
    }
  return t;
}

namespace {

float bhattacharyya(const float* p, const float* q, int bins) {
  double bc = 0.0;
  for (int b = 0; b < bins; ++b) bc += std::sqrt(double(p[b]) * q[b]);
  return static_cast<float>(std::min(1.0, bc));
}

}  // namespace

TileLikelihoods tile_likelihoods(const TileColourModels& tiles, const ColourModels& global,
                                 int min_samples) {
  const std::uint32_t g_in = global.infront_total(), g_be = global.behind_total();
  if (g_in == 0 || g_be == 0)
    throw std::invalid_argument("tile likelihoods: the global pair needs samples of both classes");
  if (static_cast<int>(global.infront.size()) != tiles.bins())
    throw std::invalid_argument("tile likelihoods: global and tile bin counts differ");
  TileLikelihoods lk;
  lk.tiles_x = tiles.tiles_x;
  lk.tiles_y = tiles.tiles_y;
  lk.tile_px = tiles.tile_px;
  lk.bins = tiles.bins();
  const auto n = static_cast<std::size_t>(tiles.tiles()) * lk.bins;
  lk.infront.assign(n, 0.0F);
  lk.behind.assign(n, 0.0F);
  lk.overlap.assign(tiles.tiles(), 0.0F);
  // Pseudo-counts of the global model: a tile with min_samples of its own is half local.
  const float m = static_cast<float>(std::max(1, min_samples));
  const auto g = global_likelihoods(global);
  for (int t = 0; t < tiles.tiles(); ++t) {
    const auto base = static_cast<std::size_t>(t) * lk.bins;
    const float n_in = float(tiles.infront_total[t]), n_be = float(tiles.behind_total[t]);
    for (int b = 0; b < lk.bins; ++b) {
      lk.infront[base + b] = (float(tiles.infront[base + b]) + m * g.infront[b]) / (n_in + m);
      lk.behind[base + b] = (float(tiles.behind[base + b]) + m * g.behind[b]) / (n_be + m);
    }
    lk.overlap[t] = bhattacharyya(&lk.infront[base], &lk.behind[base], lk.bins);
  }
  return lk;
}

TileLikelihoods global_likelihoods(const ColourModels& global) {
  const std::uint32_t g_in = global.infront_total(), g_be = global.behind_total();
  if (g_in == 0 || g_be == 0)
    throw std::invalid_argument("global likelihoods: the pair needs samples of both classes");
  TileLikelihoods lk;
  lk.tiles_x = lk.tiles_y = 1;
  lk.tile_px = 1 << 20;  // one tile covers any frame
  lk.bins = static_cast<int>(global.infront.size());
  // One pseudo-count per bin (Laplace): a colour never seen in a class is rare, not
  // impossible, so that the local prior can still outweigh it (a zero likelihood would make
  // the cost 0 or 1 whatever the neighbourhood says).
  const float bins = static_cast<float>(lk.bins);
  for (int b = 0; b < lk.bins; ++b) {
    lk.infront.push_back((float(global.infront[b]) + 1.0F) / (float(g_in) + bins));
    lk.behind.push_back((float(global.behind[b]) + 1.0F) / (float(g_be) + bins));
  }
  lk.overlap = {bhattacharyya(lk.infront.data(), lk.behind.data(), lk.bins)};
  return lk;
}

TileBlend tile_blend(const TileLikelihoods& lk, int x, int y) {
  // Tile centres sit at (t + 0.5) tile_px; beyond the outermost centres the nearest one holds.
  auto axis = [&](int p, int tiles, int& t0, int& t1, float& f) {
    const float u = (float(p) + 0.5F) / float(lk.tile_px) - 0.5F;
    const float uc = std::clamp(u, 0.0F, float(tiles - 1));
    t0 = std::min(static_cast<int>(uc), tiles - 1);
    t1 = std::min(t0 + 1, tiles - 1);
    f = uc - float(t0);
  };
  int x0, x1, y0, y1;
  float fx, fy;
  axis(x, lk.tiles_x, x0, x1, fx);
  axis(y, lk.tiles_y, y0, y1, fy);
  return {{y0 * lk.tiles_x + x0, y0 * lk.tiles_x + x1, y1 * lk.tiles_x + x0, y1 * lk.tiles_x + x1},
          {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy}};
}

ClassCounts window_class_counts(const CategoryImage& categories, int radius) {
  const int w = categories.width(), h = categories.height();
  // Integral images of the two indicator planes.
  std::vector<std::uint32_t> ii(static_cast<std::size_t>(w + 1) * (h + 1) * 2, 0);
  auto at = [&](int plane, int x, int y) -> std::uint32_t& {
    return ii[(static_cast<std::size_t>(y) * (w + 1) + x) * 2 + plane];
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto c = static_cast<Category>(categories.at(x, y));
      for (int pl = 0; pl < 2; ++pl) {
        const std::uint32_t v = (pl == 0 ? c == Category::Infront : c == Category::Behind) ? 1 : 0;
        at(pl, x + 1, y + 1) = v + at(pl, x, y + 1) + at(pl, x + 1, y) - at(pl, x, y);
      }
    }
  ClassCounts out{Image<std::uint16_t, 1>(w, h), Image<std::uint16_t, 1>(w, h)};
  const int r = std::max(0, radius);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int x0 = std::max(0, x - r), x1 = std::min(w, x + r + 1);
      const int y0 = std::max(0, y - r), y1 = std::min(h, y + r + 1);
      for (int pl = 0; pl < 2; ++pl) {
        const auto n = at(pl, x1, y1) - at(pl, x0, y1) - at(pl, x1, y0) + at(pl, x0, y0);
        (pl == 0 ? out.infront : out.behind).at(x, y) = static_cast<std::uint16_t>(n);
      }
    }
  return out;
}

LocalCost local_cost(float p_in, float p_behind, float overlap, int n_infront, int n_behind,
                     bool use_prior) {
  float ambiguity = 1.0F;
  if (use_prior) {
    // Laplace-smoothed class fractions of the window: no known neighbour -> 1/2 each.
    const float ni = float(n_infront) + 1.0F, nb = float(n_behind) + 1.0F;
    p_in *= ni / (ni + nb);
    p_behind *= nb / (ni + nb);
    ambiguity = 4.0F * ni * nb / ((ni + nb) * (ni + nb));
  }
  const float cost = p_in + p_behind > 0.0F ? p_in / (p_in + p_behind) : 0.5F;
  return {cost, std::clamp(overlap * ambiguity, 0.0F, 1.0F)};
}

LocalCosts local_costs_reference(const ImageRGB8& colour, const CategoryImage& categories,
                                 const ImageGray8& band, const DepthImage& real_depth_mm,
                                 const ImageF& virtual_depth_mm, const CvfLocalParams& params) {
  const int w = colour.width(), h = colour.height();
  if (params.tile_px < 0) throw std::invalid_argument("cvf_local: tile_px < 0");
  const CvfParams& p = params.cvf;
  LocalCosts t;
  t.global = colour_histograms_reference(colour, categories, band, p.bins_per_channel);
  const auto need = static_cast<std::uint32_t>(std::max(1, p.min_samples));
  t.colour_models_valid = t.global.infront_total() >= need && t.global.behind_total() >= need;
  if (t.colour_models_valid) {
    if (params.tile_px > 0) {
      t.tiles =
          tile_histograms_reference(colour, categories, band, p.bins_per_channel, params.tile_px);
      t.likelihoods = tile_likelihoods(t.tiles, t.global, p.min_samples);
    } else {
      t.likelihoods = global_likelihoods(t.global);
    }
  }
  const bool use_prior = params.prior_radius > 0;
  ClassCounts counts;
  if (use_prior) counts = window_class_counts(categories, params.prior_radius);
  const float global_bc = t.colour_models_valid ? global_likelihoods(t.global).overlap[0] : 0.0F;

  t.cost = ImageF(w, h);
  t.softness = ImageF(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto c = static_cast<Category>(categories.at(x, y));
      if (c != Category::Process || !t.colour_models_valid) {
        // Known categories, and the depth test without colour models: CVF's costs.
        t.cost.at(x, y) =
            cvf_cost(c, 0, t.global, false, real_depth_mm.at(x, y), virtual_depth_mm.at(x, y));
        continue;
      }
      const int bin = colour_bin(colour.at(x, y, 0), colour.at(x, y, 1), colour.at(x, y, 2),
                                 p.bins_per_channel);
      const TileBlend tb = tile_blend(t.likelihoods, x, y);
      float p_in = 0, p_be = 0;
      for (int k = 0; k < 4; ++k) {
        const auto idx = static_cast<std::size_t>(tb.tile[k]) * t.likelihoods.bins + bin;
        p_in += tb.weight[k] * t.likelihoods.infront[idx];
        p_be += tb.weight[k] * t.likelihoods.behind[idx];
      }
      const LocalCost lc =
          local_cost(p_in, p_be, global_bc, use_prior ? counts.infront.at(x, y) : 0,
                     use_prior ? counts.behind.at(x, y) : 0, use_prior);
      t.cost.at(x, y) = lc.cost;
      t.softness.at(x, y) = params.soft_where_ambiguous ? lc.softness : 0.0F;
    }
  return t;
}

CvfLocalTrace cvf_local_reference(const ImageRGB8& colour, const DepthImage& sensor_depth_mm,
                                  const ImageF& virtual_depth_mm, const CvfLocalParams& params) {
  const int w = colour.width(), h = colour.height();
  if (sensor_depth_mm.width() != w || sensor_depth_mm.height() != h ||
      virtual_depth_mm.width() != w || virtual_depth_mm.height() != h)
    throw std::invalid_argument("cvf_local_reference: colour and depth sizes differ");
  // Wide holes are near occluders (hole_core_reference.hpp), with their rims unless
  // rim_in_front is off; every step below sees them so.
  const int core_r = hole_core_radius(params.hole_core_px, w);
  const DepthImage real_depth_mm =
      params.rim_in_front ? mark_near_occluders_reference(sensor_depth_mm, core_r, &colour)
                          : fill_hole_cores_reference(sensor_depth_mm, core_r, &colour);
  const CvfParams& p = params.cvf;
  CvfLocalTrace t;
  t.categories = categorise_reference(real_depth_mm, virtual_depth_mm, p.categorise);
  t.band = process_band_reference(t.categories, p.band_px);
  auto lc =
      local_costs_reference(colour, t.categories, t.band, real_depth_mm, virtual_depth_mm, params);
  t.global = std::move(lc.global);
  t.colour_models_valid = lc.colour_models_valid;
  t.tiles = std::move(lc.tiles);
  t.likelihoods = std::move(lc.likelihoods);
  t.cost = std::move(lc.cost);
  t.softness = std::move(lc.softness);

  const auto guide = guide_from_rgb8(colour);
  t.wide = guided_filter_reference(guide, t.cost, p.wide);
  t.mask = ImageF(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto c = static_cast<Category>(t.categories.at(x, y));
      const float wide = t.wide.at(x, y);
      const float s = t.softness.at(x, y);  // 0 off process pixels: CVF's threshold there
      const float hard = wide > 0.5F ? 1.0F : 0.0F;
      t.mask.at(x, y) = c == Category::Infront ? 1.0F
                        : c == Category::Behind
                            ? 0.0F
                            : (1.0F - s) * hard + s * std::clamp(wide, 0.0F, 1.0F);
    }
  t.feather = guided_filter_reference(guide, t.mask, p.feather);
  t.alpha = visibility_from_cost(t.feather, virtual_depth_mm);
  if (params.near_occluders)
    apply_near_occluder_reference(colour, real_depth_mm, virtual_depth_mm,
                                  near_occluder_params(params), t.alpha);
  return t;
}

}  // namespace probeless::occlusion
