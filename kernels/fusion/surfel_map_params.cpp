#include "kernels/fusion/surfel_map_params.hpp"

#include <cmath>
#include <stdexcept>

namespace probeless::fusion {
namespace {

std::string size_text(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

}  // namespace

void check_surfel_map_params(const SurfelMapParams& p, const std::string& who) {
  const auto require = [&](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(who + ": " + what);
  };
  require(p.stable_confidence > 0, "stable_confidence must be > 0");
  require(p.unstable_max_unseen_frames >= 0, "unstable_max_unseen_frames must be >= 0");
  require(p.max_surfels > 0, "max_surfels must be > 0");
  require(p.region_radius_m > 0 && p.eviction_shell_m > 0, "region and shell radii must be > 0");
  require(p.index_scale >= 1 && p.index_scale <= 8, "index_scale must be in 1..8");
  require(p.depth_tolerance_m > 0 && p.normal_tolerance_rad > 0, "tolerances must be > 0");
  require(p.max_radius_factor >= 1, "max_radius_factor must be >= 1");
  require(p.normal_step_px >= 1 && p.normal_smoothing_px >= 0,
          "need normal_step_px >= 1, normal_smoothing_px >= 0");
  require(p.discontinuity_ratio > 0, "discontinuity_ratio must be > 0");
  require(p.min_depth_m > 0 && p.max_depth_m > p.min_depth_m, "need 0 < min_depth < max_depth");
  require(p.radial_sigma > 0, "radial_sigma must be > 0");
  require(p.clipped_weight_scale > 0 && p.clipped_weight_scale <= 1,
          "clipped_weight_scale must be in (0, 1]");
  require(p.black_level >= 0 && p.black_level <= p.saturated_level && p.saturated_level <= 256,
          "need 0 <= black_level <= saturated_level <= 256");
  require(p.gamma > 0, "gamma must be > 0");
  require(p.violation_margin_m > 0, "violation_margin_m must be > 0");
}

void check_surfel_frame(const std::string& who, int depth_width, int depth_height, int colour_width,
                        int colour_height, const std::array<float, 3>& radiance_per_unit,
                        const PinholeIntrinsics& k) {
  const std::string where = who + "::integrate: ";
  if (k.width <= 0 || k.height <= 0 || !(k.fx > 0) || !(k.fy > 0))
    throw std::invalid_argument(where + "intrinsics need a positive size and focal");
  if (depth_width != k.width || depth_height != k.height)
    throw std::invalid_argument(where + "depth is " + size_text(depth_width, depth_height) +
                                ", intrinsics say " + size_text(k.width, k.height));
  if (colour_width != k.width || colour_height != k.height)
    throw std::invalid_argument(where + "colour is " + size_text(colour_width, colour_height) +
                                ", intrinsics say " + size_text(k.width, k.height));
  for (float e : radiance_per_unit)
    if (!(e > 0) || !std::isfinite(e))
      throw std::invalid_argument(where + "radiance_per_unit must be > 0 and finite");
}

}  // namespace probeless::fusion
