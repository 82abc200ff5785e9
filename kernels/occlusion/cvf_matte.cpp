#include "kernels/occlusion/cvf_matte.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "kernels/occlusion/cvf_cl.hpp"

namespace probeless::occlusion {
namespace {

int low_radius(const GuidedFilterParams& p) {
  return p.subsample == 1 ? p.radius
                          : std::max(1, static_cast<int>(std::lround(double(p.radius) /
                                                                     p.subsample)));
}

void check_params(const CvfParams& p) {
  if (p.bins_per_channel < 1 || p.bins_per_channel > 16)
    throw std::invalid_argument("cvf: bins per channel must be 1..16");
  if (p.wide.subsample < 1 || p.feather.subsample != 1)
    throw std::invalid_argument("cvf: the feather filter runs at full resolution");
  if (p.band_px < 0 || p.categorise.erosion_px < 0 || p.wide.radius < 0 || p.feather.radius < 0)
    throw std::invalid_argument("cvf: negative radius");
}

}  // namespace

CvfMatte::CvfMatte(ComputeContext& ctx, const CvfParams& params)
    : ctx_(ctx),
      params_((check_params(params), params)),
      wide_(ctx, low_radius(params.wide), params.wide.eps, GuidedFilter::Output::MeanCoefficients),
      feather_(ctx, params.feather.radius, params.feather.eps,
               GuidedFilter::Output::VisibilityFromCost) {
  const auto opts = fmt::format("-DBINS={} -DSUBSAMPLE={}", params.bins_per_channel,
                                params.wide.subsample);
  auto k = [&](const char* name) { return ctx.kernel("cvf", cl_source::cvf, opts, name); };
  raw_bits_ = k("cvf_raw_bits");
  dilate_rows_ = k("cvf_dilate_rows");
  dilate_cols_ = k("cvf_dilate_cols");
  erode_ = k("cvf_erode");
  histogram_ = k("cvf_histogram");
  cost_pack_ = k("cvf_cost_pack");
  mask_pack_ = k("cvf_mask_pack");
  const int b = params.bins_per_channel;
  hist_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, sizeof(cl_uint) * 2 * b * b * b);
}

void CvfMatte::run_2d(::cl::Kernel& k, int w, int h) { ctx_.run_2d(k, w, h); }

void CvfMatte::process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  check_inputs(in, name());
  const int w = in.width(), h = in.height();
  const auto& c = ctx_.context();
  alpha.resize(c, w, h);
  if (alpha.empty()) return;
  for (auto* img : {&raw_, &tmp_, &near_, &categories_, &process_, &band_}) img->resize(c, w, h);
  const int s = params_.wide.subsample;
  const int wl = (w + s - 1) / s, hl = (h + s - 1) / s;
  wide_in_.resize(c, wl, hl);
  feather_in_.resize(c, w, h);

  // 1. Depth test and erosion (thesis 3.3.1).
  raw_bits_.setArg(0, in.real_depth_mm->buffer());
  raw_bits_.setArg(1, in.virtual_depth_mm->buffer());
  raw_bits_.setArg(2, raw_.buffer());
  raw_bits_.setArg(3, w);
  raw_bits_.setArg(4, h);
  raw_bits_.setArg(5, params_.categorise.depth_tolerance_mm);
  run_2d(raw_bits_, w, h);
  auto dilate = [&](const DeviceImageGray8& src, DeviceImageGray8& dst, int r) {
    dilate_rows_.setArg(0, src.buffer());
    dilate_rows_.setArg(1, tmp_.buffer());
    dilate_rows_.setArg(2, w);
    dilate_rows_.setArg(3, h);
    dilate_rows_.setArg(4, r);
    run_2d(dilate_rows_, w, h);
    dilate_cols_.setArg(0, tmp_.buffer());
    dilate_cols_.setArg(1, dst.buffer());
    dilate_cols_.setArg(2, w);
    dilate_cols_.setArg(3, h);
    dilate_cols_.setArg(4, r);
    run_2d(dilate_cols_, w, h);
  };
  dilate(raw_, near_, params_.categorise.erosion_px);
  erode_.setArg(0, raw_.buffer());
  erode_.setArg(1, near_.buffer());
  erode_.setArg(2, categories_.buffer());
  erode_.setArg(3, process_.buffer());
  erode_.setArg(4, w);
  erode_.setArg(5, h);
  run_2d(erode_, w, h);

  // 2. Colour models in the band around the process region (thesis 3.3.2).
  dilate(process_, band_, params_.band_px);
  const int b = params_.bins_per_channel;
  ctx_.queue().enqueueFillBuffer(hist_, cl_uint{0}, 0, sizeof(cl_uint) * 2 * b * b * b);
  const std::size_t local = 256;
  const std::size_t groups =
      std::clamp<std::size_t>((static_cast<std::size_t>(w) * h + 4095) / 4096, 1, 64);
  histogram_.setArg(0, in.color->buffer());
  histogram_.setArg(1, categories_.buffer());
  histogram_.setArg(2, band_.buffer());
  histogram_.setArg(3, w * h);
  histogram_.setArg(4, hist_);
  ctx_.queue().enqueueNDRangeKernel(histogram_, ::cl::NullRange, ::cl::NDRange(groups * local),
                                    ::cl::NDRange(local));

  // 3. Costs, packed with the guide at the wide filter's resolution (thesis 3.3.3).
  cost_pack_.setArg(0, in.color->buffer());
  cost_pack_.setArg(1, in.real_depth_mm->buffer());
  cost_pack_.setArg(2, in.virtual_depth_mm->buffer());
  cost_pack_.setArg(3, categories_.buffer());
  cost_pack_.setArg(4, hist_);
  cost_pack_.setArg(5, std::max(1, params_.min_samples));
  cost_pack_.setArg(6, w);
  cost_pack_.setArg(7, h);
  cost_pack_.setArg(8, wl);
  cost_pack_.setArg(9, hl);
  cost_pack_.setArg(10, wide_in_.buffer());
  run_2d(cost_pack_, wl, hl);

  // 4. Wide guided filter on the costs, threshold on undecided pixels (thesis 3.3.4).
  wide_.coefficients(wide_in_, wide_ab_);
  wide_.apply(wide_ab_, &wide_mean_, nullptr, nullptr, nullptr);
  mask_pack_.setArg(0, in.color->buffer());
  mask_pack_.setArg(1, categories_.buffer());
  mask_pack_.setArg(2, wide_mean_.buffer());
  mask_pack_.setArg(3, w);
  mask_pack_.setArg(4, h);
  mask_pack_.setArg(5, wl);
  mask_pack_.setArg(6, hl);
  mask_pack_.setArg(7, feather_in_.buffer());
  run_2d(mask_pack_, w, h);

  // 5. Narrow guided filter to feather; alpha = 1 - cost on the object.
  feather_.coefficients(feather_in_, feather_ab_);
  feather_.apply(feather_ab_, nullptr, &feather_in_, in.virtual_depth_mm, &alpha);
}

CvfDeviceTrace CvfMatte::download_trace() {
  auto& q = ctx_.queue();
  CvfDeviceTrace t;
  t.categories = categories_.download(q);
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
