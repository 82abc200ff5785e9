#pragma once
// CPU reference of CVF with LOCAL colour models: the proposed change to thesis 3.3.2-3.3.4
// (docs/occlusion.md, "Local colour models (proposed CVF change)", with the measurements).
//
// CVF keeps one pair of joint RGB histograms (infront / behind) per frame and costs a process
// pixel P(c|in) / (P(c|in) + P(c|behind)). Where a scene puts the same colours in front of and
// behind the virtual object, that ratio is confidently wrong and the hard threshold commits to
// it. The change, per process pixel, everything else (categories, band, guided filters) CVF's:
//   1. local likelihoods: the band's infront/behind histograms per square tile, each shrunk
//      towards the frame's global histogram with `min_samples` pseudo-counts,
//      P_t(b) = (n_t(b) + m P_global(b)) / (N_t + m), m = min_samples (the thesis's "40 samples
//      make a model": an empty tile IS the global model, a tile with m samples is half-half);
//      P_global has one pseudo-count per bin (Laplace), so no colour is impossible for a class;
//      a pixel reads the bilinear blend of its 4 nearest tile centres (no seams);
//   2. a local prior: the fractions of infront and behind pixels in the (2 r_p + 1)^2 window
//      (Laplace-smoothed counts), so cost = posterior P(infront | colour, neighbourhood);
//   3. soft where undecidable: the wide filter's output is thresholded as in CVF with weight
//      1 - s and kept as is with weight s, where s = BC x 4 pi_in pi_behind: the overlap of the
//      frame's two colour models (Bhattacharyya coefficient) times the ambiguity of the prior
//      (1 at 50/50, 0 where only one class is near). Neither cue decides -> soft, not a coin
//      toss. BC comes from the global pair, not the tiles: estimated from a few hundred
//      samples, a tile's BC is biased low (sparse histograms overlap less), and the tiles' BC
//      measured worse on 10 of 12 Middlebury cases (docs/occlusion.md).
// Without a valid global pair (< min_samples of a class in the whole band) the depth test
// decides, as in CVF (cvf_cost()).
#include <cstdint>
#include <vector>

#include "core/image.hpp"
#include "kernels/occlusion/common/cvf_params.hpp"
#include "kernels/occlusion/cvf/histogram_reference.hpp"

namespace probeless::occlusion {

// Per-tile histograms of the band's infront and behind pixels, tile (tx, ty) at index
// ty * tiles_x + tx, bins_per_channel^3 counts per class and tile.
struct TileColourModels {
  int tile_px = 32;
  int tiles_x = 0, tiles_y = 0;
  int bins_per_channel = 4;
  std::vector<std::uint32_t> infront;  // [tile * bins + bin]
  std::vector<std::uint32_t> behind;
  std::vector<std::uint32_t> infront_total;  // [tile]
  std::vector<std::uint32_t> behind_total;

  int bins() const { return bins_per_channel * bins_per_channel * bins_per_channel; }
  int tiles() const { return tiles_x * tiles_y; }
};

TileColourModels tile_histograms_reference(const ImageRGB8& colour, const CategoryImage& categories,
                                           const ImageGray8& band, int bins_per_channel,
                                           int tile_px);

// The normalised per-tile likelihoods (step 1) and each tile's Bhattacharyya coefficient.
// Requires a global pair with samples of both classes.
struct TileLikelihoods {
  int tiles_x = 0, tiles_y = 0, tile_px = 32, bins = 64;
  std::vector<float> infront;  // [tile * bins + bin], P(bin | infront)
  std::vector<float> behind;
  // [tile], sum over bins of sqrt(P_in P_behind) in [0, 1]; a diagnostic for tiles (step 3
  // uses the global pair's, global_likelihoods().overlap[0]).
  std::vector<float> overlap;
};

TileLikelihoods tile_likelihoods(const TileColourModels& tiles, const ColourModels& global,
                                 int min_samples);

// The global pair as a 1x1 grid covering any image (tile_px = 0 in the params).
TileLikelihoods global_likelihoods(const ColourModels& global);

// The 4 nearest tile centres of pixel (x, y) and their bilinear weights (summing to 1).
struct TileBlend {
  int tile[4];
  float weight[4];
};
TileBlend tile_blend(const TileLikelihoods& lk, int x, int y);

// Counts of infront and behind pixels in the clipped (2r+1)^2 window of every pixel.
struct ClassCounts {
  Image<std::uint16_t, 1> infront, behind;
};
ClassCounts window_class_counts(const CategoryImage& categories, int radius);

// Cost of a process pixel and its soft weight s (steps 1-3) from the blended likelihoods, the
// global pair's overlap and the window counts. Exposed for the tests and as the device kernel's
// definition.
struct LocalCost {
  float cost;
  float softness;
};
LocalCost local_cost(float p_in, float p_behind, float overlap, int n_infront, int n_behind,
                     bool use_prior);

// Steps 1-3 up to the wide filter, from the categories and band (the part the device stage
// cvf_local_histogram.cl computes): cost and softness of every pixel.
struct LocalCosts {
  ColourModels global;
  bool colour_models_valid = false;  // the global pair had >= min_samples per class
  TileColourModels tiles;            // empty with tile_px = 0 or without colour models
  TileLikelihoods likelihoods;       // empty without colour models
  ImageF cost;
  ImageF softness;  // s of step 3 (0 off process pixels and without colour models)
};
LocalCosts local_costs_reference(const ImageRGB8& colour, const CategoryImage& categories,
                                 const ImageGray8& band, const DepthImage& real_depth_mm,
                                 const ImageF& virtual_depth_mm, const CvfLocalParams& params);

struct CvfLocalTrace {
  CategoryImage categories;
  ImageGray8 band;
  ColourModels global;
  bool colour_models_valid = false;  // the global pair had >= min_samples per class
  TileColourModels tiles;
  TileLikelihoods likelihoods;
  ImageF cost;
  ImageF softness;  // s of step 3 (0 off process pixels and without colour models)
  ImageF wide;
  ImageF mask;
  ImageF feather;
  ImageF alpha;  // visibility of the virtual object, 0 off it
};

CvfLocalTrace cvf_local_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                                  const ImageF& virtual_depth_mm,
                                  const CvfLocalParams& params = {});

}  // namespace probeless::occlusion
