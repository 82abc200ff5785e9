// The CPU reference of CVF with local colour models on hand-made inputs with known answers:
// scenes where CVF's global model cannot decide and the local one can, the fallback to the
// global model (pseudo-counts) and to the depth test, seam-free blending across tiles, and
// the local prior's window counts against brute force.
#include "kernels/occlusion/cvf/cvf_local_reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/occlusion/common/categorise_reference.hpp"
#include "kernels/occlusion/cvf/cvf_reference.hpp"

namespace probeless::occlusion {
namespace {

constexpr std::uint16_t kNear = 500, kFar = 2000;  // real depths around a 1000 mm object
const std::uint8_t kColourA[3] = {200, 40, 40};
const std::uint8_t kColourB[3] = {40, 40, 200};

struct Scene {
  ImageRGB8 colour;
  DepthImage depth;
  ImageF virt;
  ImageF truth;  // visibility, on process pixels
};

Scene blank_scene(int w, int h) {
  return {ImageRGB8(w, h), DepthImage(w, h), ImageF(w, h, 1000.0F), ImageF(w, h)};
}
void paint(Scene& s, int x, int y, const std::uint8_t* rgb) {
  for (int k = 0; k < 3; ++k) s.colour.at(x, y, k) = rgb[k];
}

// 128x64, two halves that swap roles: on the left colour A (rows < 32) is in front of the
// virtual object and colour B (rows >= 32) behind it; on the right A is behind and B in front.
// Rows 22..41 have no depth (process). Globally A and B are each half infront, half behind, so
// CVF's pair of histograms cannot tell them apart; per 64 px tile they separate perfectly.
Scene swapped_halves() {
  Scene s = blank_scene(128, 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 128; ++x) {
      const bool top = y < 32, left = x < 64;
      paint(s, x, y, top ? kColourA : kColourB);
      const bool infront = top == left;
      s.truth.at(x, y) = infront ? 0.0F : 1.0F;
      s.depth.at(x, y) = (y >= 22 && y < 42) ? 0 : (infront ? kNear : kFar);
    }
  return s;
}

CvfLocalParams exact_categories() {
  CvfLocalParams p;
  p.cvf.categorise.erosion_px = 0;  // the hand-made categories are exact
  // The hand-made holes are process pixels for the colour models to decide, not surfaces
  // nearer than the sensor's range (hole cores: near_occluder_test.cpp).
  p.hole_core_px = 0;
  return p;
}

TEST(CvfLocalReference, LocalTilesDecideWhereTheGlobalModelCannot) {
  const Scene s = swapped_halves();
  CvfLocalParams local = exact_categories();
  local.tile_px = 64;
  CvfLocalParams global = local;
  global.tile_px = 0;
  const auto tl = cvf_local_reference(s.colour, s.depth, s.virt, local);
  const auto tg = cvf_local_reference(s.colour, s.depth, s.virt, global);
  ASSERT_TRUE(tl.colour_models_valid);
  EXPECT_NEAR(tg.likelihoods.overlap[0], 1.0F, 1e-5F);  // identical global histograms
  EXPECT_LT(tl.likelihoods.overlap[0], 0.5F);           // own samples dominate: 640 vs 40 pseudo
  // Rows 28..35 are more than 3 px from any known pixel: only colour can decide there.
  // Columns up to the left tile's centre (32) and from the right one's (96) read one tile.
  double err_local = 0, err_global = 0;
  int n = 0;
  for (int y = 28; y < 36; ++y)
    for (int x : {0, 10, 20, 31, 96, 110, 127}) {
      const float hidden = 1.0F - s.truth.at(x, y);
      EXPECT_NEAR(tl.cost.at(x, y), hidden, 0.1F) << x << "," << y;
      EXPECT_NEAR(tg.cost.at(x, y), 0.5F, 1e-5F) << x << "," << y;
      err_local += std::pow(tl.alpha.at(x, y) - s.truth.at(x, y), 2);
      err_global += std::pow(tg.alpha.at(x, y) - s.truth.at(x, y), 2);
      ++n;
    }
  EXPECT_LT(err_local / n, 0.01);
  EXPECT_GT(err_global / n, 0.1);
}

// A behind region crossed by a vertical line of depth holes (what the Kinect model leaves at
// a depth edge between two background surfaces) whose colour is common in the infront class
// elsewhere and rare (1 in 16) in the behind class. CVF's global cost (16:1 for infront)
// hides the line; the local prior (every known neighbour is behind, 36:1) keeps it visible.
// (Had the colour never been seen behind, the colour evidence would still win: the prior
// outweighs moderate colour evidence, not near-certain evidence.)
TEST(CvfLocalReference, LocalPriorKeepsHoleLinesInsideARegion) {
  Scene s = blank_scene(96, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 96; ++x) {
      const bool infront_block = x < 24;
      const bool hole_line = x >= 60 && x < 62;
      const bool sprinkle = (x + 3 * y) % 16 == 0;
      paint(s, x, y, infront_block || hole_line || sprinkle ? kColourA : kColourB);
      s.depth.at(x, y) = hole_line ? 0 : (infront_block ? kNear : kFar);
    }
  // Process pixels also at the left block's edge, so that the band holds infront samples.
  for (int y = 0; y < 48; ++y) s.depth.at(24, y) = 0;
  CvfParams cvf;
  cvf.categorise.erosion_px = 0;
  const auto old = cvf_reference(s.colour, s.depth, s.virt, cvf);
  const auto neu = cvf_local_reference(s.colour, s.depth, s.virt, exact_categories());
  ASSERT_TRUE(old.colour_models_valid);
  for (int y = 4; y < 44; y += 8) {
    EXPECT_LT(old.alpha.at(60, y), 0.5F) << "the thesis's global model hides the line, y " << y;
    EXPECT_GT(neu.alpha.at(60, y), 0.9F) << y;
    EXPECT_GT(neu.alpha.at(61, y), 0.9F) << y;
  }
}

TEST(CvfLocalReference, TileModelsShrinkTowardsTheGlobalModel) {
  ColourModels g8{2, std::vector<std::uint32_t>(8, 0), std::vector<std::uint32_t>(8, 0)};
  g8.infront = {40, 0, 0, 0, 0, 0, 0, 40};  // P_global(in) = 1/2 on bins 0 and 7
  g8.behind = {0, 80, 0, 0, 0, 0, 0, 0};
  TileColourModels tiles;
  tiles.tile_px = 8;
  tiles.tiles_x = 3;
  tiles.tiles_y = 1;
  tiles.bins_per_channel = 2;
  tiles.infront.assign(24, 0);
  tiles.behind.assign(24, 0);
  tiles.infront_total = {0, 40, 4000};
  tiles.behind_total = {0, 0, 0};
  tiles.infront[8 + 3] = 40;     // tile 1: min_samples of its own, all in bin 3
  tiles.infront[16 + 3] = 4000;  // tile 2: far more than min_samples
  const auto lk = tile_likelihoods(tiles, g8, 40);
  // The global model with one pseudo-count per bin (Laplace).
  auto g_in = [&](int b) { return (g8.infront[b] + 1.0F) / (80.0F + 8.0F); };
  auto g_be = [&](int b) { return (g8.behind[b] + 1.0F) / (80.0F + 8.0F); };
  for (int b = 0; b < 8; ++b) {
    // An empty tile IS the global model.
    EXPECT_FLOAT_EQ(lk.infront[b], g_in(b));
    EXPECT_FLOAT_EQ(lk.behind[b], g_be(b));
    // No behind samples anywhere local: every tile's behind model is the global one.
    EXPECT_FLOAT_EQ(lk.behind[8 + b], g_be(b));
    EXPECT_GT(lk.behind[b], 0.0F);  // never impossible
  }
  // min_samples of its own: half local, half global.
  EXPECT_FLOAT_EQ(lk.infront[8 + 3], 0.5F + 0.5F * g_in(3));
  EXPECT_FLOAT_EQ(lk.infront[8 + 0], 0.5F * g_in(0));
  // Many samples: almost purely local.
  EXPECT_NEAR(lk.infront[16 + 3], 1.0F, 0.01F);
  for (int t = 0; t < 3; ++t) {
    float sum = 0;
    for (int b = 0; b < 8; ++b) sum += lk.infront[t * 8 + b];
    EXPECT_NEAR(sum, 1.0F, 1e-5F);
  }
  EXPECT_THROW(
      tile_likelihoods(
          tiles,
          ColourModels{2, std::vector<std::uint32_t>(8, 1), std::vector<std::uint32_t>(8, 0)}, 40),
      std::invalid_argument);
}

TEST(CvfLocalReference, WithoutAGlobalPairTheDepthTestDecides) {
  // Only infront and process pixels: no behind samples, so no colour model at all.
  Scene s = blank_scene(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      paint(s, x, y, (x + y) % 2 ? kColourA : kColourB);
      s.depth.at(x, y) = x < 20 ? kNear : (x < 30 ? 0 : 995);  // 995: a tie, process
    }
  const auto t = cvf_local_reference(s.colour, s.depth, s.virt, exact_categories());
  EXPECT_FALSE(t.colour_models_valid);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      const auto c = static_cast<Category>(t.categories.at(x, y));
      EXPECT_FLOAT_EQ(t.cost.at(x, y),
                      cvf_cost(c, 0, t.global, false, s.depth.at(x, y), s.virt.at(x, y)))
          << x << "," << y;
      EXPECT_EQ(t.softness.at(x, y), 0.0F);
    }
  EXPECT_FLOAT_EQ(t.cost.at(25, 3), 0.5F);  // unknown depth
  EXPECT_FLOAT_EQ(t.cost.at(35, 3), 1.0F);  // 995 < 1000: the depth test says in front
}

TEST(CvfLocalReference, BlendIsContinuousAcrossTileBorders) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  TileLikelihoods lk;
  lk.tiles_x = 5;
  lk.tiles_y = 3;
  lk.tile_px = 16;
  lk.bins = 1;
  for (int t = 0; t < 15; ++t) {
    lk.infront.push_back(u(rng));
    lk.behind.push_back(u(rng));
    lk.overlap.push_back(u(rng));
  }
  auto blended = [&](int x, int y) {
    const auto tb = tile_blend(lk, x, y);
    float v = 0, wsum = 0;
    for (int k = 0; k < 4; ++k) {
      EXPECT_GE(tb.weight[k], 0.0F);
      v += tb.weight[k] * lk.infront[tb.tile[k]];
      wsum += tb.weight[k];
    }
    EXPECT_NEAR(wsum, 1.0F, 1e-5F);
    return v;
  };
  // A tile's own value at its centre (the blend interpolates, it does not smooth away).
  EXPECT_NEAR(blended(2 * 16 + 8, 1 * 16 + 8), lk.infront[1 * 5 + 2], 0.04F);
  // Neighbouring pixels differ by at most the largest tile difference over one tile width:
  // no step at the borders x = 16, 32, ... (a per-tile lookup would jump by up to 1 there).
  for (int y = 0; y < 3 * 16; ++y)
    for (int x = 0; x + 1 < 5 * 16; ++x) {
      EXPECT_LE(std::fabs(blended(x + 1, y) - blended(x, y)), 1.0F / 16 + 1e-5F) << x << "," << y;
      if (y + 1 < 3 * 16) {
        EXPECT_LE(std::fabs(blended(x, y + 1) - blended(x, y)), 1.0F / 16 + 1e-5F) << x << "," << y;
      }
    }
}

TEST(CvfLocalReference, CostIsTheLocalPosterior) {
  // Colour says infront 10:1, but all 48 known neighbours are behind: behind wins.
  const auto lc = local_cost(0.5F, 0.05F, 0.8F, 0, 48, true);
  EXPECT_NEAR(lc.cost, 10.0F / (10.0F + 49.0F), 1e-5F);
  EXPECT_NEAR(lc.softness, 0.8F * 4.0F * 49.0F / (50.0F * 50.0F), 1e-5F);
  // Balanced neighbours: colour alone decides, softness = the models' overlap.
  const auto even = local_cost(0.5F, 0.05F, 0.8F, 20, 20, true);
  EXPECT_NEAR(even.cost, 10.0F / 11.0F, 1e-5F);
  EXPECT_NEAR(even.softness, 0.8F, 1e-5F);
  // Without the prior: CVF's likelihood ratio.
  EXPECT_NEAR(local_cost(0.5F, 0.05F, 0.3F, 0, 48, false).cost, 10.0F / 11.0F, 1e-5F);
  EXPECT_FLOAT_EQ(local_cost(0.0F, 0.0F, 0.3F, 0, 0, true).cost, 0.5F);
}

TEST(CvfLocalReference, WindowCountsMatchBruteForce) {
  std::mt19937 rng(3);
  for (const auto& [w, h, r] : {std::tuple{1, 1, 3}, {17, 5, 2}, {31, 23, 3}, {40, 9, 0}}) {
    CategoryImage cats(w, h);
    for (auto& v : cats.elements()) v = static_cast<std::uint8_t>(rng() % 4);
    const auto counts = window_class_counts(cats, r);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        int ni = 0, nb = 0;
        for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
          for (int i = std::max(0, x - r); i <= std::min(w - 1, x + r); ++i) {
            ni += cats.at(i, j) == std::uint8_t(Category::Infront);
            nb += cats.at(i, j) == std::uint8_t(Category::Behind);
          }
        EXPECT_EQ(counts.infront.at(x, y), ni);
        EXPECT_EQ(counts.behind.at(x, y), nb);
      }
  }
}

TEST(CvfLocalReference, TileHistogramsPartitionTheGlobalOne) {
  const Scene s = swapped_halves();
  CategoriseParams cp;
  cp.erosion_px = 0;
  const auto cats = categorise_reference(s.depth, s.virt, cp);
  const auto band = process_band_reference(cats, 10);
  const auto global = colour_histograms_reference(s.colour, cats, band, 4);
  for (int tile : {1, 7, 16, 64, 200}) {
    const auto t = tile_histograms_reference(s.colour, cats, band, 4, tile);
    for (int b = 0; b < 64; ++b) {
      std::uint32_t in = 0, be = 0;
      for (int k = 0; k < t.tiles(); ++k) {
        in += t.infront[static_cast<std::size_t>(k) * 64 + b];
        be += t.behind[static_cast<std::size_t>(k) * 64 + b];
      }
      EXPECT_EQ(in, global.infront[b]) << tile;
      EXPECT_EQ(be, global.behind[b]) << tile;
    }
  }
  EXPECT_THROW(tile_histograms_reference(s.colour, cats, band, 4, 0), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::occlusion
