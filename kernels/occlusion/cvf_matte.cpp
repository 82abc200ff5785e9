#include "kernels/occlusion/cvf_matte.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "kernels/occlusion/cvf_cl.hpp"
#include "kernels/occlusion/cvf_kernel_args.hpp"

namespace probeless::occlusion {
namespace {

int low_radius(const GuidedFilterParams& p) {
  return p.subsample == 1
             ? p.radius
             : std::max(1, static_cast<int>(std::lround(double(p.radius) / p.subsample)));
}

const CvfParams& checked(const CvfParams& p) {
  if (p.bins_per_channel < 1 || p.bins_per_channel > 16)
    throw std::invalid_argument("cvf: bins per channel must be 1..16");
  if (p.wide.subsample < 1 || p.feather.subsample != 1)
    throw std::invalid_argument("cvf: wide subsample must be >= 1, the feather filter full-res");
  if (p.band_px < 0 || p.wide.radius < 0 || p.feather.radius < 0)
    throw std::invalid_argument("cvf: negative radius");
  return p;
}

}  // namespace

CvfMatte::CvfMatte(ComputeContext& ctx, const CvfParams& params)
    : ctx_(ctx),
      params_(checked(params)),
      categoriser_(ctx, params.categorise),
      wide_(ctx, low_radius(params.wide), params.wide.eps, GuidedFilter::Output::MeanCoefficients),
      feather_(ctx, params.feather.radius, params.feather.eps,
               GuidedFilter::Output::VisibilityFromCost) {
  const auto opts =
      fmt::format("-DBINS={} -DSUBSAMPLE={}", params.bins_per_channel, params.wide.subsample);
  auto k = [&](const char* name) { return ctx.kernel("cvf", cl_source::cvf, opts, name); };
  histogram_ = k("cvf_histogram");
  cost_pack_ = k("cvf_cost_pack");
  mask_pack_ = k("cvf_mask_pack");
  const int b = params.bins_per_channel;
  hist_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, sizeof(cl_uint) * 2 * b * b * b);
}

void CvfMatte::stage_done(const char* stage) {
  if (!profiling_) return;
  ctx_.queue().finish();
  const auto now = std::chrono::steady_clock::now();
  stage_times_.push_back(
      {stage, std::chrono::duration<double, std::milli>(now - stage_start_).count()});
  stage_start_ = now;
}

void CvfMatte::process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  check_inputs(in, name());
  stage_times_.clear();
  if (profiling_) {
    ctx_.queue().finish();
    stage_start_ = std::chrono::steady_clock::now();
  }
  const int w = in.width(), h = in.height();
  const auto& c = ctx_.context();
  alpha.resize(c, w, h);
  if (alpha.empty()) return;
  const int s = params_.wide.subsample;
  const int wl = (w + s - 1) / s, hl = (h + s - 1) / s;
  wide_in_.resize(c, wl, hl);
  feather_in_.resize(c, w, h);
  // 1. Depth test and erosion (thesis 3.3.1).
  categoriser_.run(in);
  const auto& categories = categoriser_.categories().buffer();
  stage_done("categories");

  // 2. Colour models in the band around the process region (thesis 3.3.2).
  categoriser_.dilate(categoriser_.process_mask(), band_, params_.band_px);
  stage_done("band");
  const int b = params_.bins_per_channel;
  ctx_.queue().enqueueFillBuffer(hist_, cl_uint{0}, 0, sizeof(cl_uint) * 2 * b * b * b);
  const std::size_t local = 256;
  const std::size_t groups =
      std::clamp<std::size_t>((static_cast<std::size_t>(w) * h + 8191) / 8192, 1, 64);
  set_args(histogram_, in.color->buffer(), categories, band_.buffer(), w * h, hist_);
  ctx_.queue().enqueueNDRangeKernel(histogram_, ::cl::NullRange, ::cl::NDRange(groups * local),
                                    ::cl::NDRange(local));
  stage_done("histograms");

  // 3. Costs, packed with the guide at the wide filter's resolution (thesis 3.3.3).
  set_args(cost_pack_, in.color->buffer(), in.real_depth_mm->buffer(),
           in.virtual_depth_mm->buffer(), categories, hist_, std::max(1, params_.min_samples), w, h,
           wl, hl, wide_in_.buffer());
  run_pixels(ctx_, cost_pack_, wl, hl);
  stage_done("costs");

  // 4. Wide guided filter on the costs, threshold on undecided pixels (thesis 3.3.4).
  wide_.coefficients(wide_in_, wide_ab_);
  wide_.apply(wide_ab_, &wide_mean_, nullptr, nullptr, nullptr);
  stage_done("wide filter");
  set_args(mask_pack_, in.color->buffer(), categories, wide_mean_.buffer(), w, h, wl, hl,
           feather_in_.buffer());
  run_pixels(ctx_, mask_pack_, w, h);
  stage_done("threshold");

  // 5. Narrow guided filter to feather; alpha = 1 - cost on the object.
  feather_.coefficients(feather_in_, feather_ab_);
  stage_done("feather coefficients");
  feather_.apply(feather_ab_, nullptr, &feather_in_, in.virtual_depth_mm, &alpha);
  stage_done("feather apply");
}

CvfDeviceTrace CvfMatte::download_trace() {
  auto& q = ctx_.queue();
  CvfDeviceTrace t;
  t.categories = categoriser_.categories().download(q);
  t.band = band_.download(q);
  const int b = params_.bins_per_channel, n = b * b * b;
  std::vector<cl_uint> hist(2 * static_cast<std::size_t>(n));
  q.enqueueReadBuffer(hist_, CL_TRUE, 0, sizeof(cl_uint) * hist.size(), hist.data());
  t.models = {b, std::vector<std::uint32_t>(hist.begin(), hist.begin() + n),
              std::vector<std::uint32_t>(hist.begin() + n, hist.end())};
  t.wide_input = wide_in_.download(q);
  t.feather_input = feather_in_.download(q);
  return t;
}

}  // namespace probeless::occlusion
