#pragma once
// Parameters and pixel categories of cost-volume-filtering occlusion (thesis ch. 3, VRST
// 2017). Every default is the author's value unless docs/occlusion.md says otherwise.
#include <cstdint>
#include <string>

#include "core/image.hpp"

namespace probeless::occlusion {

// What the depth test says about a pixel (thesis 3.3.1). "Infront" means the *real* surface
// is in front of the virtual object, so the real thing hides the virtual one.
enum class Category : std::uint8_t {
  Ignore = 0,   // not on the virtual object
  Behind = 1,   // real surface behind the virtual object: the object is visible
  Infront = 2,  // real surface in front: the object is hidden
  Process = 3,  // on the object, depth unknown, within the tolerance, or near a depth edge
};

using CategoryImage = Image<std::uint8_t, 1>;  // values of Category

struct CategoriseParams {
  // |real - virtual| <= tolerance(virtual) is undecided ("process"): the sensor cannot tell
  // the two surfaces apart there, which is what decides a virtual object standing on a real
  // surface (issue #19 item 6, docs/occlusion.md "Right at contact"); Direct takes it too. The
  // thesis names no tolerance. tolerance(v) = depth_tolerance_mm + tolerance_per_mm (v -
  // tolerance_z0_mm)^2 (depth_tolerance_mm()). k sigma_z(v) of the Kinect axial noise model
  // (Nguyen, Izadi & Lovell 2012, sigma_z = 1.2 mm + 0.0019 (z - 0.4 m)^2 / m, as
  // core/depth_noise.hpp uses it) is {1.2 k, 3, 0.0019e-3 k, 400}; with k = 3 and 4 it measured
  // worse than the default on Middlebury (mean 10.45 and 10.60 vs 10.28) and at 0.8 m on a
  // slanted table (the model leaves out the grid shift on a depth slope): docs/occlusion.md.
  // Default: a fixed 15 mm, above the model's axial noise at 1.5 m (ours).
  float depth_tolerance_mm = 15.0F;
  // Infront/behind pixels closer than this to another on-object category become "process":
  // lateral depth noise at silhouettes (thesis 3.3.1: 3 px).
  int erosion_px = 3;
  // The tolerance's depth-dependent part (after erosion_px so that {tolerance, erosion}
  // initialisers keep their meaning).
  float tolerance_per_mm = 0.0F;
  float tolerance_z0_mm = 400.0F;
};

// The depth test's tolerance at virtual depth v (mm); the devices compute it in this order.
inline float depth_tolerance_mm(const CategoriseParams& p, float virtual_mm) {
  const float d = virtual_mm - p.tolerance_z0_mm;
  float q = d * d;
  q = p.tolerance_per_mm * q;
  return p.depth_tolerance_mm + q;
}

// -D options of the kernels that run the depth test: TOL_QUAD and TOL_Z0 (hex floats).
std::string depth_tolerance_options(const CategoriseParams& p);

struct GuidedFilterParams {
  int radius = 6;
  float eps = 0.0025F;  // on intensities in [0, 1]
  // 1: the exact filter. s > 1: He & Sun's fast guided filter (2015), coefficients computed
  // on an s-times subsampled guide with radius max(1, round(r / s)) and upsampled bilinearly.
  int subsample = 1;
};

struct CvfParams {
  CategoriseParams categorise;
  int band_px = 10;          // colour samples come from this close to the process region
  int min_samples = 40;      // per class, else the depth test decides (thesis 3.3.2)
  int bins_per_channel = 4;  // joint RGB histogram: 4^3 = 64 bins (author's code)
  // Cost filter (author's r and eps); computed at half resolution by default (He & Sun's fast
  // guided filter: the whole frame 3.65 instead of 5.4 CPU-ms on PoCL, MSE 0.36 % above the
  // exact one's, docs/occlusion.md "Speed").
  GuidedFilterParams wide{6, 0.0025F, 2};
  GuidedFilterParams feather{1, 0.3F, 1};  // after the threshold (author's code)
};

// The shipped CVF ("cvf", docs/occlusion.md "CVF as shipped"): CVF's parameters with the two
// filter settings measured better (docs/occlusion.md):
// the wide filter at r = 3 px, exact (the 3 px of the erosion: a window centred in the eroded
// band reaches the known pixels on both sides and no further), and the feather filter with the
// wide filter's eps (the author's 0.3 exceeds any colour variance, so it blurred every edge).
inline CvfParams cvf_local_filter_defaults() {
  CvfParams p;
  p.wide = {3, 0.0025F, 1};
  p.feather = {1, 0.0025F, 1};
  return p;
}

// The shipped CVF's parameters: CVF's and the local colour models' (cvf_local_reference.hpp).
struct CvfLocalParams {
  CvfParams cvf = cvf_local_filter_defaults();
  // Side of a colour-model tile, px; 0 = the global pair only (CVF's model + steps 2 and 3).
  int tile_px = 32;
  // Window of the local prior (step 2): the thesis's 3 px of lateral depth-edge uncertainty.
  int prior_radius = 3;
  // Step 3; false = CVF's hard threshold on every process pixel.
  bool soft_where_ambiguous = true;
  // Cap the visibility of pixels without depth whose colour the background does not explain
  // (near_occluder_reference.hpp: occluders nearer than the sensor's minimum range, thesis
  // 3.6, issue #19 item 4). Off by default: it matted a hand without depth at MSE 18e-3
  // instead of 88e-3, but raised the Middlebury mean from 10.28e-3 to 14.5e-3, whose Kinect-model
  // holes it also capped (docs/occlusion.md "Occluders the sensor cannot see").
  bool near_occluders = false;
  // Holes wider than 2 r + 1 px are surfaces nearer than the sensor's minimum range: their
  // cores (hole mask eroded by r) take part as "in front" (hole_core_reference.hpp, issue #19
  // item 4). r in px at 640 px width, scaled with the frame's (hole_core_radius()); 0 = off.
  // 20: the widest that leaves the Middlebury mean as it was (10.28e-3; 16 raised it to
  // 10.46e-3 through ArtL's wide holes) and still mattes a hand at 0.45 m within 2x of the same
  // hand with depth (docs/occlusion.md "Occluders the sensor cannot see").
  int hole_core_px = 20;
  // With hole cores: the near occluder's rim (the holes near a core that take the core's colour
  // rather than the measured surface's beside them, mark_near_occluders_reference()) is "in
  // front" too, not left to the colour models. On the sim's near hand cvf's MSE 3.72e-3 ->
  // 1.00e-3 (seed 2: 3.42e-3 -> 0.97e-3) and the stabiliser's noise factor x0.730 -> x0.512
  // (x0.707 -> x0.543), arm only x0.535 -> x0.471; Middlebury and alphamatting unchanged (their
  // holes make no cores; docs/occlusion.md "The rim that follows the occluder").
  bool rim_in_front = true;
};

// Costs (probability that the real surface hides the object), thesis 3.3.3.
inline constexpr float kCostInfront = 1.0F;
inline constexpr float kCostBehind = 0.0F;
inline constexpr float kCostIgnore = 0.5F;

// Joint RGB histogram bin of an 8-bit colour: (r_bin * B + g_bin) * B + b_bin.
inline int colour_bin(std::uint8_t r, std::uint8_t g, std::uint8_t b, int bins_per_channel) {
  const int rb = r * bins_per_channel / 256;
  const int gb = g * bins_per_channel / 256;
  const int bb = b * bins_per_channel / 256;
  return (rb * bins_per_channel + gb) * bins_per_channel + bb;
}

}  // namespace probeless::occlusion
