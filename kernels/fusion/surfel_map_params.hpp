#pragma once
// What the HDR surfel map of issue #21 item 1 (thesis 6.2.2, 6.2.6; docs/fusion.md) is made of
// and its parameters, shared by the CPU reference (surfel_map_reference.hpp) and the device
// map (surfel_map.hpp) so that both run one rule set.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/camera/pinhole.hpp"

namespace probeless::fusion {

// Why a surfel's colour is less trusted: the pixel it was born from was clipped.
enum SurfelFlag : std::uint8_t {
  kBornSaturated = 1 << 0,  // a channel at the 8-bit ceiling: radiance is a lower bound
  kBornBlack = 1 << 1,      // every channel under the floor: radiance is an upper bound
};

struct Surfel {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();  // world, metres
  Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();   // world, unit, towards its observers
  float radius = 0;                                    // metres
  float confidence = 0;                                // sum of observation weights
  std::array<float, 3> radiance{};                     // linear HDR colour (fisheye units)
  std::uint8_t flags = 0;                              // SurfelFlag bits
  std::int64_t created_frame = 0;
  std::int64_t last_seen_frame = 0;
};

struct SurfelMapParams {
  // 6.2.2: surfels below this are "unstable": rendered, not tracked against. 10 is
  // ElasticFusion's c_stable (Whelan et al. 2016), not checked against the thesis text.
  float stable_confidence = 10;
  // Unstable surfels not seen for more than this many frames are deleted (6.2.2, 6.2.6).
  // ElasticFusion deletes a surfel still unstable 20 frames after its birth; counting from
  // its last sighting instead keeps a half-built object that is still in view.
  int unstable_max_unseen_frames = 20;
  // The budget (issue #21 item 1): at most max_surfels, kept in a sphere around the virtual
  // content; pixels outside it are not fused at all. 64 bytes a surfel: 200 000 is 12.8 MB.
  std::size_t max_surfels = 200000;
  Eigen::Vector3f region_centre = Eigen::Vector3f::Zero();  // world; set_region_centre moves it
  float region_radius_m = 1.0f;
  // Over budget: evicted farthest shell first, lowest confidence first within a shell; the
  // shell keeps confidence deciding among surfels at about the same distance (ours).
  float eviction_shell_m = 0.05f;
  // Correspondence (6.2.2): the index map is rendered at index_scale x the depth resolution
  // per axis and a depth pixel searches its index_scale^2 cells; a match lies within
  // depth_tolerance_m of the pixel's depth and its normal within normal_tolerance_rad
  // (ElasticFusion's 0.05 m and 0.5 rad; the thesis gives the 4x4 window, not the limits).
  int index_scale = 4;
  float depth_tolerance_m = 0.05f;
  float normal_tolerance_rad = 0.5f;
  // Radius (6.2.2 after ElasticFusion): r = sqrt(2) d / f / |n_z|, at most max_radius_factor
  // times the facing-camera radius, so grazing pixels do not make metre-wide discs.
  float max_radius_factor = 2.0f;
  // Normals (6.2.2) from central differences over +-normal_step_px of the depth smoothed over
  // +-normal_smoothing_px: the sim's Kinect-like depth (core/depth_noise.hpp) comes in 3 px
  // dot cells with ~4 mm noise at 1.7 m, and on raw +-3 px differences one pixel in ten
  // failed the 0.5 rad match on a static view of box_appears and was born again every frame;
  // smoothed over +-3 px, one in 200 (ours; ElasticFusion filters the depth bilaterally).
  int normal_step_px = 3;
  int normal_smoothing_px = 3;
  // A neighbour farther than this fraction of the depth from the centre pixel is across a
  // silhouette: no normal there, no surfel, and not smoothed across (ours).
  float discontinuity_ratio = 0.05f;
  float min_depth_m = 0.3f, max_depth_m = 5.0f;
  // Observation weight exp(-g^2 / (2 sigma^2)), g the pixel's distance from the principal
  // point over the half diagonal: image corners are the least trusted (ElasticFusion; Keller
  // et al. 2013 sigma 0.6).
  float radial_sigma = 0.6f;
  // 6.2.2: saturated or black pixels give a lower initial confidence (and colour weight when
  // fused); the thesis says lower, the factor is ours.
  float clipped_weight_scale = 0.25f;
  int saturated_level = 255;  // any 8-bit channel >= this: saturated
  int black_level = 3;        // every channel < this: black (colour_exposure's "<= 2")
  double gamma = 2.2;         // linear = (8-bit / 255)^gamma, as kernels/hdr/colour_exposure
  // 6.2.6 depth violations: a surfel this far in front of the observed depth (the nearest in
  // the 3 x 3 pixels around where it projects, so silhouettes do not count) is removed.
  float violation_margin_m = 0.05f;
};

// What one integrate() did, for tests and the docs' measurements.
struct SurfelIntegrationStats {
  std::size_t candidates = 0;  // valid pixels in the region with a normal
  std::size_t fused = 0;       // matched an existing surfel
  std::size_t born = 0;        // became new surfels
  std::size_t removed_violation = 0, removed_unstable = 0, evicted = 0;
};

// Throws std::invalid_argument "<who>: ..." for params out of range (a non-positive threshold,
// radius, tolerance or budget, index_scale outside 1..8, normal_step_px < 1, gamma <= 0,
// black_level > saturated_level or levels outside 0..256).
void check_surfel_map_params(const SurfelMapParams& params, const std::string& who);

// Throws std::invalid_argument "<who>::integrate: ..." when the intrinsics have no positive
// size or focal, either image's size is not the intrinsics' (naming both sizes), or a radiance
// scale is not positive and finite.
void check_surfel_frame(const std::string& who, int depth_width, int depth_height, int colour_width,
                        int colour_height, const std::array<float, 3>& radiance_per_unit,
                        const PinholeIntrinsics& k);

}  // namespace probeless::fusion
