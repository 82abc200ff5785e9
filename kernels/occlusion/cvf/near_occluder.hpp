#pragma once
// The device stage of near_occluder_reference.hpp: caps CVF's visibility on the object's
// pixels without depth where their colour is not the local background's (issue #19 item 4).
// Three small kernels after the matte: histograms, q per pixel, the cap.
#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/occlusion/cvf/near_occluder_reference.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless::occlusion {

class NearOccluder {
 public:
  // Throws std::invalid_argument for bins outside 1..8 or tile_px < 1.
  NearOccluder(ComputeContext& ctx, const NearOccluderParams& params);
  // Caps `alpha` (the in's size) in place; enqueues and does not wait.
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha);

 private:
  ComputeContext& ctx_;
  NearOccluderParams params_;
  ::cl::Kernel histograms_, background_, apply_;
  DeviceImage<float, 1> q_;
  ::cl::Buffer hist_;  // near_occluder.cl's layout, for hist_words_ words
  std::size_t hist_words_ = 0;
  int bins_;
};

}  // namespace probeless::occlusion
