#pragma once
// Occluders the depth sensor cannot see (issue #19 item 4, thesis 3.6): a hand closer than the
// sensor's minimum range has no depth, so CVF's categories call it "process" with no "in
// front" samples near it, and the behind side's prior and colour models leave it visible. Its
// colour still tells it apart from what is behind the object there. On the object:
//   P_hole: the frame's colour histogram of the pixels without depth;
//   P_behind: the local one of the pixels whose real surface is behind the object (depth
//     test), from the 3x3 tiles around the pixel, shrunk towards the frame's with min_samples
//     pseudo-counts as the local colour models are (cvf_local_reference.hpp step 1);
// both with one pseudo-count per bin. A pixel without depth is a dropout of the local
// background as far as the background explains its colour, q = min(1, P_behind(c) / P_hole(c)),
// and near (something the sensor cannot see) with 1 - q. As CVF's local prior does for the
// depth classes, the neighbourhood weighs in: m = the Laplace-smoothed mean nearness of the
// object's pixels in the (2 r + 1)^2 window (known depth counts 0, r = CVF's prior radius, the
// thesis's 3 px), and the visibility is capped at the posterior
//   cap = q (1 - m) / (q (1 - m) + (1 - q) m).
// Skin in a hole with no skin behind the object near it is hidden; a hole in the wall's colour
// (a depth shadow beside a nearer surface, a dark patch) stays as CVF matted it; a hand pixel
// whose colour the wall shares is hidden when its neighbours are. Measured in
// tests/kernels/cvf_local/near_occluder_test.cpp and docs/occlusion.md: it is not good enough
// to ship (CvfLocalParams::near_occluders is off). Local because depth
// shadows sample only the background next to them: with the frame's background model, the capped
// wall colours of the shadow of a hand WITH depth raised that scene's MSE from 0.97e-3 to 6.8e-3
// (tests/kernels/cvf_local/ near_occluder_test.cpp). With fewer than min_samples of either class
// nothing changes.
#include <array>
#include <cstdint>
#include <vector>

#include "core/image.hpp"

namespace probeless::occlusion {

struct NearOccluderParams {
  float depth_tolerance_mm = 15.0F;  // CVF's depth test (CategoriseParams)
  // Finer than CVF's 4 (64 bins): colour alone decides here, with no prior and no filter,
  // and at 4 bins skin and a beige wall share a bin (near_occluder_test.cpp: the hand without
  // depth at MSE 18.6e-3 with 4 bins per channel, 18.0e-3 with 8).
  int bins_per_channel = 8;
  int min_samples = 40;  // CVF's "40 samples make a model" (thesis 3.3.2)
  int tile_px = 32;      // the local colour models' tiles (CvfLocalParams)
  int prior_radius = 3;  // the local prior's window (CvfLocalParams)
};

// CVF's depth tolerance, minimum samples and tile size.
struct CvfLocalParams;
NearOccluderParams near_occluder_params(const CvfLocalParams& params);

// The frame's hole and behind histograms (bins^3 each), their totals, and the behind
// histograms per tile ([tile * bins + bin], tile = ty * tiles_x + tx) with their totals.
struct HoleColourModels {
  std::vector<std::uint32_t> hole, behind;
  std::uint32_t hole_total = 0, behind_total = 0;
  int tiles_x = 0, tiles_y = 0;
  std::vector<std::uint32_t> tile_behind, tile_behind_total;
};
HoleColourModels hole_colour_models(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                                    const ImageF& virtual_depth_mm, const NearOccluderParams& p);

// q above for a pixel without depth at (x, y) of colour bin b; 1 without enough samples.
float background_explains(const HoleColourModels& m, const NearOccluderParams& p, int x, int y,
                          int bin);

// alpha (CVF's visibility) capped on the object's pixels without depth.
void apply_near_occluder_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                                   const ImageF& virtual_depth_mm, const NearOccluderParams& p,
                                   ImageF& alpha);

}  // namespace probeless::occlusion
