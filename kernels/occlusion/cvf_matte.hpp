#pragma once
// Cost-volume-filtering occlusion on the device (thesis ch. 3; docs/occlusion.md): depth
// categories with eroded borders, colour histograms in a band around the undecided region,
// per-pixel costs, a wide guided filter, a threshold, a narrow guided filter. Everything stays
// on the device between stages; cvf_reference.hpp is the CPU twin the tests compare with.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/occlusion/categorise.hpp"
#include "kernels/occlusion/cvf_params.hpp"
#include "kernels/occlusion/guided_filter.hpp"
#include "kernels/occlusion/histogram_reference.hpp"
#include "kernels/occlusion/occlusion_method.hpp"

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

class CvfMatte final : public OcclusionMethod {
 public:
  CvfMatte(ComputeContext& ctx, const CvfParams& params = {});
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

  ComputeContext& ctx_;
  CvfParams params_;
  Categoriser categoriser_;
  ::cl::Kernel histogram_, cost_pack_, mask_pack_;
  GuidedFilter wide_, feather_;
  DeviceImageGray8 band_;
  ::cl::Buffer hist_;
  DeviceImageF4 wide_in_, wide_ab_, wide_mean_, feather_in_, feather_ab_;
  bool profiling_ = false;
  std::vector<CvfStageTime> stage_times_;
  std::chrono::steady_clock::time_point stage_start_;
};

}  // namespace probeless::occlusion
