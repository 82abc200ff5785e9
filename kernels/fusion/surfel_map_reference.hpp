#pragma once
// The HDR surfel map of issue #21 item 1 (thesis 6.2.2, 6.2.6; docs/fusion.md "The surfel map
// (CPU reference)"): the real geometry near the virtual content as oriented discs with a
// linear-radiance colour, fused frame by frame from the tracked RGB-D stream. Plain C++: the
// reference the OpenCL map (surfel_map.hpp) is tested against, so every rule is sequential and
// deterministic (the same frames give the same map, surfel for surfel). Cost on one core of
// the 2-core Xeon VM (tests' DISABLED_Cost*): 66-73 ms p50 for a 640 x 480 frame with every
// pixel in the region (~300 000 surfels), 6-8 ms for the sim's view with a 0.5 m region.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"
#include "kernels/fusion/surfel_map_params.hpp"

namespace probeless::fusion {

class SurfelMap {
 public:
  // Throws std::invalid_argument for params out of range (check_surfel_map_params).
  explicit SurfelMap(SurfelMapParams params = {});

  // One registered RGB-D frame: depth (mm, 0 = unknown) and colour of intrinsics' size, the
  // camera at T_world_camera, colour in the light model's units as radiance_per_unit x
  // linear 8-bit (ColourExposureEstimate::e). Throws std::invalid_argument when either image's
  // size is not the intrinsics', an intrinsic is not positive, or a radiance scale is not
  // positive and finite.
  SurfelIntegrationStats integrate(const DepthImage& depth, const ImageRGB8& colour,
                                   const std::array<float, 3>& radiance_per_unit,
                                   const PinholeIntrinsics& intrinsics, const Pose& T_world_camera,
                                   std::int64_t frame_index);

  // The virtual content moved: the budget's sphere follows it from the next frame on.
  void set_region_centre(const Eigen::Vector3f& centre) { params_.region_centre = centre; }

  const std::vector<Surfel>& surfels() const { return surfels_; }
  std::size_t size() const { return surfels_.size(); }
  std::size_t stable_count() const;
  bool is_stable(const Surfel& s) const { return s.confidence >= params_.stable_confidence; }
  const SurfelMapParams& params() const { return params_; }

 private:
  SurfelMapParams params_;
  std::vector<Surfel> surfels_;
  std::array<float, 256> linear_{};  // 8-bit -> linear, params_.gamma
  // The index map (index_scale x depth size): surfel index + 1 per cell, 0 empty, and the
  // cells written this frame so clearing costs the surfels, not the 16 x larger map.
  std::vector<std::uint32_t> index_map_;
  std::vector<std::uint32_t> touched_cells_;
  std::vector<float> camera_z_;  // per surfel, this frame's view depth (the index map's z test)
  std::vector<float> smoothed_;  // metres, the depth the normals are taken from; < 0 not yet
};

}  // namespace probeless::fusion
