#pragma once
// The device stage of CVF with local colour models (cvf_local_histogram.cl; the CPU twin is
// local_costs_reference() in cvf_local_reference.hpp): per-tile colour histograms in one pass
// with local-memory counts, the shrunk per-tile likelihoods, and per pixel the local-posterior
// cost and the softness of the threshold. CvfMatte's tile layout (GPUs) runs it in place of
// the thesis's histogram and cost steps; the strip layout (CPUs) fuses the same steps into its
// row-streaming kernels and shares only cvf_local_likelihoods.
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
  // The frame's pair (infront [0, n), behind [n, 2n), n = bins^3) and the tiles' pairs
  // ([tile][2n]) of the last run, for traces.
  const ::cl::Buffer& global_histogram() const { return hist_; }
  const ::cl::Buffer& tile_histograms() const { return tile_hist_; }
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
