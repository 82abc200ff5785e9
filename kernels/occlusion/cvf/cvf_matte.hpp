#pragma once
// Cost-volume-filtering occlusion on the device (thesis ch. 3; docs/occlusion.md): depth
// categories with eroded borders, colour histograms in a band around the undecided region,
// per-pixel costs, a wide guided filter, a threshold, a narrow guided filter. Everything stays
// on the device between stages; cvf_reference.hpp is the CPU twin the tests compare with.
// Per frame: one fill and three row-streaming kernels (cvf.cl: categories, band and
// histograms; cvf_guided.cl twice: costs + wide filter, threshold + feather filter).
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "kernels/occlusion/common/categorise.hpp"
#include "kernels/occlusion/common/cvf_params.hpp"
#include "kernels/occlusion/common/guided_filter.hpp"
#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/occlusion/cvf/cvf_guided.hpp"
#include "kernels/occlusion/cvf/histogram_reference.hpp"

namespace probeless::occlusion {

// Intermediates of the last process() call, downloaded for tests.
struct CvfDeviceTrace {
  CategoryImage categories;
  ImageGray8 band;  // 1 inside the band (not 255)
  ColourModels models;
  Image<float, 4> wide_input;     // (r, g, b, cost) at the wide filter's resolution
  Image<float, 4> feather_input;  // (r, g, b, mask) at full resolution
};

// Wall time of one stage of the last process() call, with the queue drained before and after
// (profiling mode only: the finish() calls serialise the stages).
struct CvfStageTime {
  std::string stage;
  double ms = 0;
};

// How the stage is laid out on the device. Strips: one fill and three row-streaming kernels
// that do their own SIMD in float16, one work-item per strip of rows (cvf.cl, cvf_guided.cl):
// the fast layout on CPU devices (docs/occlusion.md "Speed"), but a GPU would run a handful of
// work-items. Tiles: per-pixel kernels and the two-pass tile guided filter (cvf_tiles.cl,
// cvf_categorise.cl, guided_filter.cl), the earlier layout, many small work-groups for GPUs.
// Auto: Strips on CPU devices, Tiles elsewhere.
enum class CvfLayout { Auto, Strips, Tiles };

class CvfMatte final : public OcclusionMethod {
 public:
  // With `trace`, the filters also store their inputs for download_trace() (tests).
  CvfMatte(ComputeContext& ctx, const CvfParams& params = {}, bool trace = false,
           CvfLayout layout = CvfLayout::Auto);
  CvfLayout layout() const { return layout_; }
  std::string name() const override { return "cvf"; }
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) override;

  const CvfParams& params() const { return params_; }
  CvfDeviceTrace download_trace();

  // Profiling mode: process() waits for the queue after every stage and records the times in
  // stage_times(). Off by default, where nothing waits.
  void set_profiling(bool on) { profiling_ = on; }
  const std::vector<CvfStageTime>& stage_times() const { return stage_times_; }

 private:
  void stage_done(const char* stage);
  void process_strips(const OcclusionInputs& in, DeviceImage<float, 1>& alpha);
  void process_tiles(const OcclusionInputs& in, DeviceImage<float, 1>& alpha);
  // Histogram buffer: infront and behind counts, then their two totals.
  std::size_t hist_bytes() const {
    const std::size_t b = params_.bins_per_channel;
    return sizeof(cl_uint) * (2 * b * b * b + 2);
  }

  ComputeContext& ctx_;
  CvfParams params_;
  bool trace_;
  CvfLayout layout_;
  ::cl::Buffer hist_;
  // Strips.
  ::cl::Kernel classify_;
  std::optional<StripGuidedFilter> wide_, feather_;
  DeviceImageGray8 categories_;  // Category in bits 0-1, the band in bit 2 (cvf.cl)
  ::cl::Buffer classify_scratch_;
  std::size_t classify_scratch_bytes_ = 0;
  // Planar images: plane c of a w x h image is rows [c h, (c + 1) h) of a w x 4h image.
  DeviceImageF wide_mean_, wide_in_, feather_in_;
  // Tiles.
  std::optional<Categoriser> categoriser_;
  ::cl::Kernel histogram_, cost_pack_, mask_pack_;
  std::optional<GuidedFilter> tile_wide_, tile_feather_;
  DeviceImageGray8 band_;
  DeviceImageF4 tile_wide_in_, tile_wide_ab_, tile_wide_mean_, tile_feather_in_, tile_feather_ab_;
  bool profiling_ = false;
  std::vector<CvfStageTime> stage_times_;
  std::chrono::steady_clock::time_point stage_start_;
};

}  // namespace probeless::occlusion
