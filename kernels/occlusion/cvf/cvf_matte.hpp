#pragma once
// Cost-volume-filtering occlusion on the device (thesis ch. 3; docs/occlusion.md): depth
// categories with eroded borders, colour histograms in a band around the undecided region,
// per-pixel costs, a wide guided filter, a threshold, a narrow guided filter. Everything stays
// on the device between stages.
//
// Two methods, one stage:
//   "cvf" (the shipped one, CvfLocalParams): local colour models per 32 px tile shrunk towards
//     the frame's, a local prior, softness where the models overlap (docs/occlusion.md "CVF as
//     shipped"); its CPU twin is cvf_local_reference.hpp.
//   "cvf_thesis" (CvfParams): the thesis's CVF, one pair of colour models per frame; the
//     baseline the evaluator compares with; its CPU twin is cvf_reference.hpp.
// Per frame on CPUs: two fills and four kernels (cvf.cl: categories, band, histograms per
// frame and tile, prior counts; cvf_local_likelihoods per tile; cvf_guided.cl twice: costs +
// wide filter, threshold + feather filter); the thesis's method skips the tiles and prior.
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
#include "kernels/occlusion/cvf/cvf_local_histogram.hpp"
#include "kernels/occlusion/cvf/cvf_local_reference.hpp"
#include "kernels/occlusion/cvf/histogram_reference.hpp"
#include "kernels/occlusion/cvf/hole_core.hpp"
#include "kernels/occlusion/cvf/hole_core_reference.hpp"
#include "kernels/occlusion/cvf/near_occluder.hpp"

namespace probeless::occlusion {

// Intermediates of the last process() call, downloaded for tests.
struct CvfDeviceTrace {
  CategoryImage categories;
  ImageGray8 band;  // 1 inside the band (not 255)
  ColourModels models;
  TileColourModels tiles;         // "cvf" only (empty for "cvf_thesis")
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
  // "cvf": the shipped method. With `trace`, the filters also store their inputs for
  // download_trace() (tests). Throws std::invalid_argument for parameters the device cannot
  // run (tile_px < 1, bins > 8, prior radius > 7, radii > 16).
  explicit CvfMatte(ComputeContext& ctx, const CvfLocalParams& params = {}, bool trace = false,
                    CvfLayout layout = CvfLayout::Auto);
  // "cvf_thesis": the thesis's CVF with one pair of colour models per frame.
  CvfMatte(ComputeContext& ctx, const CvfParams& thesis, bool trace = false,
           CvfLayout layout = CvfLayout::Auto);
  CvfLayout layout() const { return layout_; }
  std::string name() const override { return local_ ? "cvf" : "cvf_thesis"; }
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) override;
  // With hole_core_px > 0: the depth with every near occluder (cores and the rims that take
  // their colour) marked, HoleCoreFill::mark_near_occluders(); with rim_in_front (the default)
  // the depth CVF judged by itself.
  const DeviceImage<std::uint16_t, 1>* judged_depth() override;

  // The common part (categories, band, models, filters); local_params() has the rest.
  const CvfParams& params() const { return params_.cvf; }
  const CvfLocalParams& local_params() const { return params_; }
  bool local_models() const { return local_; }
  CvfDeviceTrace download_trace();

  // Profiling mode: process() waits for the queue after every stage and records the times in
  // stage_times(). Off by default, where nothing waits.
  void set_profiling(bool on) { profiling_ = on; }
  const std::vector<CvfStageTime>& stage_times() const { return stage_times_; }

 private:
  CvfMatte(ComputeContext& ctx, const CvfLocalParams& params, bool local, bool trace,
           CvfLayout layout);
  void stage_done(const char* stage);
  int tiles_x(int w) const { return (w + params_.tile_px - 1) / params_.tile_px; }
  int tiles_y(int h) const { return (h + params_.tile_px - 1) / params_.tile_px; }
  void process_strips(const OcclusionInputs& in, DeviceImage<float, 1>& alpha);
  // The classify kernel's outputs outside `rows`, known without a look (process_strips()).
  void fill_known_rows(const PixelRect& rows, int w, int h);
  void process_tiles(const OcclusionInputs& in, DeviceImage<float, 1>& alpha);
  // Histogram buffer: infront and behind counts, then their two totals.
  std::size_t hist_bytes() const {
    const std::size_t b = params_.cvf.bins_per_channel;
    return sizeof(cl_uint) * (2 * b * b * b + 2);
  }

  ComputeContext& ctx_;
  CvfLocalParams params_;
  bool local_;
  bool trace_;
  CvfLayout layout_;
  ::cl::Buffer hist_;
  // Strips.
  ::cl::Kernel classify_;
  std::optional<StripGuidedFilter> wide_, feather_;
  DeviceImageGray8 categories_;  // Category in bits 0-1, the band in bit 2 (cvf.cl)
  ::cl::Buffer classify_scratch_;
  std::size_t classify_scratch_bytes_ = 0;
  ::cl::Buffer row_object_;  // per row: the columns [begin, end) of the object (cvf.cl)
  int row_object_rows_ = 0;
  // Local colour models: the tiles' histograms, their likelihoods, the frame's overlap and
  // validity (cvf_local_histogram.cl's layout) and the prior's window counts.
  ::cl::Kernel likelihoods_;
  ::cl::Buffer tile_hist_, lik_, overlap_, stats_;
  int tiles_capacity_ = 0;
  DeviceImage<std::uint8_t, 2> prior_;
  // Planar images: plane c of a w x h image is rows [c h, (c + 1) h) of a w x 4h image.
  DeviceImageF wide_mean_, wide_in_, feather_in_;
  // Tiles.
  std::optional<Categoriser> categoriser_;
  std::optional<CvfLocalHistogram> local_costs_;
  std::optional<NearOccluder> near_;        // cvf with near_occluders (issue #19 item 4)
  std::optional<HoleCoreFill> hole_cores_;  // cvf with hole_core_px > 0 (issue #19 item 4)
  bool cores_run_ = false;                  // the last process() ran the hole cores
  const DeviceImage<std::uint8_t, 3>* colour_ = nullptr;         // the last process()'s
  const DeviceImage<std::uint16_t, 1>* judged_depth_ = nullptr;  // marked, once asked
  ::cl::Kernel histogram_, cost_pack_, mask_pack_;
  std::optional<GuidedFilter> tile_wide_, tile_feather_;
  DeviceImageGray8 band_;
  DeviceImageF4 tile_wide_in_, tile_wide_ab_, tile_wide_mean_, tile_feather_in_, tile_feather_ab_;
  bool profiling_ = false;
  std::vector<CvfStageTime> stage_times_;
  std::chrono::steady_clock::time_point stage_start_;
};

}  // namespace probeless::occlusion
