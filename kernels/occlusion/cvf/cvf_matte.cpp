#include "kernels/occlusion/cvf/cvf_matte.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "kernels/occlusion/common/cvf_kernel_args.hpp"
#include "kernels/occlusion/cvf/cvf_cl.hpp"
#include "kernels/occlusion/cvf/cvf_tiles_cl.hpp"
#include "kernels/occlusion/cvf/cvf_vector_cl.hpp"

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

std::string cvf_options(const CvfParams& p) {
  return fmt::format("-DBINS={} -DSUBSAMPLE={}", p.bins_per_channel, p.wide.subsample);
}

// A w x 4h planar image (4 planes of w x h) as an interleaved 4-channel one.
Image<float, 4> from_planes(const ImageF& planes) {
  const int w = planes.width(), h = planes.height() / 4;
  Image<float, 4> out(w, h);
  for (int c = 0; c < 4; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) out.at(x, y, c) = planes.at(x, c * h + y);
  return out;
}

}  // namespace

CvfLayout resolve(CvfLayout layout, const ComputeContext& ctx) {
  if (layout != CvfLayout::Auto) return layout;
  return ctx.info().type == "CPU" ? CvfLayout::Strips : CvfLayout::Tiles;
}

CvfMatte::CvfMatte(ComputeContext& ctx, const CvfParams& params, bool trace, CvfLayout layout)
    : ctx_(ctx), params_(checked(params)), trace_(trace), layout_(resolve(layout, ctx)) {
  hist_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, hist_bytes());
  if (layout_ == CvfLayout::Tiles) {
    categoriser_.emplace(ctx, params.categorise);
    tile_wide_.emplace(ctx, low_radius(params.wide), params.wide.eps,
                       GuidedFilter::Output::MeanCoefficients);
    tile_feather_.emplace(ctx, params.feather.radius, params.feather.eps,
                          GuidedFilter::Output::VisibilityFromCost);
    auto k = [&](const char* name) {
      return ctx.kernel("cvf_tiles", cl_source::cvf_tiles, cvf_options(params), name);
    };
    histogram_ = k("cvf_histogram");
    cost_pack_ = k("cvf_cost_pack");
    mask_pack_ = k("cvf_mask_pack");
    return;
  }
  if (params.categorise.erosion_px > 16 || params.band_px > 16)
    throw std::invalid_argument("cvf: erosion and band radii must be <= 16");
  wide_.emplace(ctx, low_radius(params.wide), params.wide.eps, StripGuidedFilter::Input::CvfCost,
                StripGuidedFilter::Output::MeanCoefficients, cvf_options(params), trace);
  feather_.emplace(ctx, params.feather.radius, params.feather.eps,
                   StripGuidedFilter::Input::CvfFeather,
                   StripGuidedFilter::Output::VisibilityFromCost, cvf_options(params), trace);
  static const std::string source =
      std::string(cl_source::cvf_vector) + std::string(cl_source::cvf);
  classify_ = ctx.kernel("cvf", source,
                         fmt::format("{} -DEROSION={} -DBAND={}", cvf_options(params),
                                     std::max(0, params.categorise.erosion_px), params.band_px),
                         "cvf_classify");
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
  if (layout_ == CvfLayout::Tiles) {
    process_tiles(in, alpha);
  } else {
    process_strips(in, alpha);
  }
}

void CvfMatte::process_tiles(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  const int w = in.width(), h = in.height();
  const auto& c = ctx_.context();
  alpha.resize(c, w, h);
  if (alpha.empty()) return;
  const int s = params_.wide.subsample;
  const int wl = (w + s - 1) / s, hl = (h + s - 1) / s;
  tile_wide_in_.resize(c, wl, hl);
  tile_feather_in_.resize(c, w, h);
  // 1. Depth test and erosion (thesis 3.3.1).
  categoriser_->run(in);
  const auto& categories = categoriser_->categories().buffer();
  stage_done("categories");
  // 2. Colour models in the band around the process region (thesis 3.3.2).
  categoriser_->dilate(categoriser_->process_mask(), band_, params_.band_px);
  stage_done("band");
  ctx_.queue().enqueueFillBuffer(hist_, cl_uint{0}, 0, hist_bytes());
  const std::size_t local = 256;
  const std::size_t groups =
      std::clamp<std::size_t>((static_cast<std::size_t>(w) * h + 8191) / 8192, 1, 64);
  set_args(histogram_, in.colour->buffer(), categories, band_.buffer(), w * h, hist_);
  ctx_.queue().enqueueNDRangeKernel(histogram_, ::cl::NullRange, ::cl::NDRange(groups * local),
                                    ::cl::NDRange(local));
  stage_done("histograms");
  // 3. Costs, packed with the guide at the wide filter's resolution (thesis 3.3.3).
  set_args(cost_pack_, in.colour->buffer(), in.real_depth_mm->buffer(),
           in.virtual_depth_mm->buffer(), categories, hist_, std::max(1, params_.min_samples), w, h,
           wl, hl, tile_wide_in_.buffer());
  run_pixels(ctx_, cost_pack_, wl, hl);
  stage_done("costs");
  // 4. Wide guided filter on the costs, threshold on undecided pixels (thesis 3.3.4).
  tile_wide_->coefficients(tile_wide_in_, tile_wide_ab_);
  tile_wide_->apply(tile_wide_ab_, &tile_wide_mean_, nullptr, nullptr, nullptr);
  stage_done("wide filter");
  set_args(mask_pack_, in.colour->buffer(), categories, tile_wide_mean_.buffer(), w, h, wl, hl,
           tile_feather_in_.buffer());
  run_pixels(ctx_, mask_pack_, w, h);
  stage_done("threshold");
  // 5. Narrow guided filter to feather; alpha = 1 - cost on the object.
  tile_feather_->coefficients(tile_feather_in_, tile_feather_ab_);
  stage_done("feather coefficients");
  tile_feather_->apply(tile_feather_ab_, nullptr, &tile_feather_in_, in.virtual_depth_mm, &alpha);
  stage_done("feather apply");
}

void CvfMatte::process_strips(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  const int w = in.width(), h = in.height();
  const auto& c = ctx_.context();
  alpha.resize(c, w, h);
  if (alpha.empty()) return;
  const int s = params_.wide.subsample;
  const int wl = (w + s - 1) / s, hl = (h + s - 1) / s;
  wide_mean_.resize(c, wl + 2 * StripGuidedFilter::kMeanPad, 4 * hl);
  if (trace_) {
    wide_in_.resize(c, wl, 4 * hl);
    feather_in_.resize(c, w, 4 * h);
  }
  // 1.-2. Depth test, erosion, band and colour models in one pass (thesis 3.3.1-3.3.2).
  categories_.resize(c, w, h);
  const auto& categories = categories_.buffer();
  ctx_.queue().enqueueFillBuffer(hist_, cl_uint{0}, 0, hist_bytes());
  {
    // A strip walks 2 (erosion + band) rows outside it (cvf.cl).
    const int strips =
        StripGuidedFilter::strip_count(h, 2 * (params_.categorise.erosion_px + params_.band_px),
                                       static_cast<int>(ctx_.info().compute_units));
    const int strip_rows = (h + strips - 1) / strips;
    const int groups = (h + strip_rows - 1) / strip_rows;
    const std::size_t srow = StripGuidedFilter::scratch_row(w);
    const std::size_t rows = 2 * params_.categorise.erosion_px + 2 + 3 + 2 * params_.band_px + 2;
    const std::size_t bytes = sizeof(float) * srow * rows * groups;
    if (bytes > classify_scratch_bytes_) {
      classify_scratch_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, bytes);
      classify_scratch_bytes_ = bytes;
    }
    set_args(classify_, w, h, strip_rows, params_.categorise.depth_tolerance_mm, classify_scratch_,
             in.real_depth_mm->buffer(), in.virtual_depth_mm->buffer(), in.colour->buffer(),
             categories, hist_);
    ctx_.queue().enqueueNDRangeKernel(classify_, ::cl::NullRange,
                                      ::cl::NDRange(1, static_cast<std::size_t>(groups)),
                                      ::cl::NDRange(1, 1));
  }
  stage_done("categories + band + histograms");

  // 3.-4. Costs (thesis 3.3.3), computed inside the wide guided filter at its resolution.
  {
    auto& k = wide_->kernel();
    set_args_from(k, StripGuidedFilter::kFirstArg, in.colour->buffer(), categories,
                  in.real_depth_mm->buffer(), in.virtual_depth_mm->buffer(), hist_,
                  std::max(1, params_.min_samples), w, h, wide_mean_.buffer());
    if (trace_) k.setArg(StripGuidedFilter::kFirstArg + 9, wide_in_.buffer());
    wide_->run(wl, hl);
  }
  stage_done("costs + wide filter");

  // 5. Threshold (thesis 3.3.4) inside the narrow guided filter that feathers; alpha = 1 - cost.
  {
    auto& k = feather_->kernel();
    set_args_from(k, StripGuidedFilter::kFirstArg, in.colour->buffer(), categories,
                  wide_mean_.buffer(), wl, hl, in.virtual_depth_mm->buffer(), alpha.buffer());
    if (trace_) k.setArg(StripGuidedFilter::kFirstArg + 7, feather_in_.buffer());
    feather_->run(w, h);
  }
  stage_done("threshold + feather");
}

CvfDeviceTrace CvfMatte::download_trace() {
  auto& q = ctx_.queue();
  CvfDeviceTrace t;
  if (layout_ == CvfLayout::Tiles) {
    t.categories = categoriser_->categories().download(q);
    t.band = band_.download(q);
    t.wide_input = tile_wide_in_.download(q);
    t.feather_input = tile_feather_in_.download(q);
  } else {
    const auto packed = categories_.download(q);
    t.categories = CategoryImage(packed.width(), packed.height());
    t.band = ImageGray8(packed.width(), packed.height());
    for (std::size_t i = 0; i < packed.elements().size(); ++i) {
      t.categories.elements()[i] = packed.elements()[i] & 3;
      t.band.elements()[i] = (packed.elements()[i] >> 2) & 1;
    }
    if (trace_) {
      t.wide_input = from_planes(wide_in_.download(q));
      t.feather_input = from_planes(feather_in_.download(q));
    }
  }
  const int b = params_.bins_per_channel, n = b * b * b;
  std::vector<cl_uint> hist(2 * static_cast<std::size_t>(n) + 2);
  q.enqueueReadBuffer(hist_, CL_TRUE, 0, sizeof(cl_uint) * hist.size(), hist.data());
  t.models = {b, std::vector<std::uint32_t>(hist.begin(), hist.begin() + n),
              std::vector<std::uint32_t>(hist.begin() + n, hist.begin() + 2 * n)};
  return t;
}

}  // namespace probeless::occlusion
