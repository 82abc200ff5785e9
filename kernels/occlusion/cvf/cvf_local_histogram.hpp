#pragma once
// The device stage of CVF with local colour models (cvf_local_histogram.cl; the CPU twin is
// local_costs_reference() in cvf_local_reference.hpp): per-tile colour histograms in one pass
// with local-memory counts, the shrunk per-tile likelihoods, and per pixel the local-posterior
// cost and the softness of the threshold. It replaces CVF's histogram and cost steps; it is
// not wired into CvfMatte (docs/occlusion.md "Local colour models" says how it would be).
#include <cstdint>

#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/occlusion/cvf/cvf_local_reference.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless::occlusion {

class CvfLocalHistogram {
 public:
  // Throws std::invalid_argument unless tile_px > 0 and bins_per_channel is 1..8 (the pair of
  // histograms must fit a work-group's local memory: 2 x 512 counts at 8 bins).
  CvfLocalHistogram(ComputeContext& ctx, const CvfLocalParams& params);

  // Colour and depths from `in`; categories and band as CVF's categoriser and dilation write
  // them (Category values; band != 0 within band_px of a process pixel). Enqueues only.
  void run(const OcclusionInputs& in, const DeviceImageGray8& categories,
           const DeviceImageGray8& band);

  const DeviceImageF& cost() const { return cost_; }
  const DeviceImageF& softness() const { return softness_; }
  // Blocking: whether the last run had a global pair with >= min_samples per class.
  bool colour_models_valid();

 private:
  ComputeContext& ctx_;
  CvfLocalParams params_;
  ::cl::Kernel histogram_, likelihoods_, count_rows_, cost_kernel_;
  ::cl::Buffer hist_, tile_hist_, lik_, overlap_, stats_;
  DeviceImage<std::uint8_t, 2> row_counts_;  // the prior's per-row window counts (in, behind)
  int tiles_capacity_ = 0;
  DeviceImageF cost_, softness_;
};

}  // namespace probeless::occlusion
