#include "kernels/occlusion/cvf/cvf_local_histogram.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "kernels/occlusion/cvf/cvf_local_histogram_cl.hpp"

namespace probeless::occlusion {
namespace {

const CvfLocalParams& checked(const CvfLocalParams& p) {
  if (p.tile_px < 1) throw std::invalid_argument("cvf_local_histogram: tile_px must be >= 1");
  if (p.cvf.bins_per_channel < 1 || p.cvf.bins_per_channel > 8)
    throw std::invalid_argument("cvf_local_histogram: bins per channel must be 1..8");
  if (p.prior_radius < 0 || p.prior_radius > 127)
    throw std::invalid_argument("cvf_local_histogram: prior_radius must be 0..127");
  return p;
}

}  // namespace

CvfLocalHistogram::CvfLocalHistogram(ComputeContext& ctx, const CvfLocalParams& params)
    : ctx_(ctx), params_(checked(params)) {
  const auto opts =
      fmt::format("-DBINS={} -DTILE={} -DPRIOR_RADIUS={} -DSOFT={}", params.cvf.bins_per_channel,
                  params.tile_px, params.prior_radius, params.soft_where_ambiguous ? 1 : 0);
  auto k = [&](const char* name) {
    return ctx.kernel("cvf_local_histogram", cl_source::cvf_local_histogram, opts, name);
  };
  histogram_ = k("cvf_local_tile_histogram");
  likelihoods_ = k("cvf_local_likelihoods");
  cost_kernel_ = k("cvf_local_cost");
  if (params.prior_radius > 0) count_rows_ = k("cvf_local_count_rows");
  const int b = params.cvf.bins_per_channel;
  hist_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, sizeof(cl_uint) * 2 * b * b * b);
  stats_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, sizeof(cl_int));
  overlap_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, sizeof(cl_float));
}

void CvfLocalHistogram::run(const OcclusionInputs& in, const DeviceImageGray8& categories,
                            const DeviceImageGray8& band) {
  check_inputs(in, "cvf_local_histogram");
  const int w = in.width(), h = in.height();
  if (!categories.same_size(w, h) || !band.same_size(w, h))
    throw std::invalid_argument("cvf_local_histogram: categories or band differ in size");
  cost_.resize(ctx_.context(), w, h);
  softness_.resize(ctx_.context(), w, h);
  if (cost_.empty()) return;
  const int t = params_.tile_px;
  const int tiles_x = (w + t - 1) / t, tiles_y = (h + t - 1) / t, tiles = tiles_x * tiles_y;
  const int b = params_.cvf.bins_per_channel, nbins = b * b * b;
  if (tiles > tiles_capacity_) {
    const auto n = static_cast<std::size_t>(tiles) * 2 * nbins;
    tile_hist_ = ::cl::Buffer(ctx_.context(), CL_MEM_READ_WRITE, sizeof(cl_uint) * n);
    lik_ = ::cl::Buffer(ctx_.context(), CL_MEM_READ_WRITE, sizeof(cl_float) * n);
    tiles_capacity_ = tiles;
  }
  auto& q = ctx_.queue();
  q.enqueueFillBuffer(hist_, cl_uint{0}, 0, sizeof(cl_uint) * 2 * nbins);

  // 1. One work-group per tile; 16 x 16 items (fewer when the device allows less).
  const std::size_t max = std::max<std::size_t>(1, ctx_.info().max_work_group_size);
  const std::size_t lx = std::min<std::size_t>(16, max);
  const std::size_t ly = std::max<std::size_t>(1, std::min<std::size_t>(16, max / lx));
  histogram_.setArg(0, in.colour->buffer());
  histogram_.setArg(1, categories.buffer());
  histogram_.setArg(2, band.buffer());
  histogram_.setArg(3, w);
  histogram_.setArg(4, h);
  histogram_.setArg(5, tile_hist_);
  histogram_.setArg(6, hist_);
  q.enqueueNDRangeKernel(histogram_, ::cl::NullRange, ::cl::NDRange(tiles_x * lx, tiles_y * ly),
                         ::cl::NDRange(lx, ly));

  // 2. One work-item per tile.
  likelihoods_.setArg(0, tile_hist_);
  likelihoods_.setArg(1, hist_);
  likelihoods_.setArg(2, tiles);
  likelihoods_.setArg(3, params_.cvf.min_samples);
  likelihoods_.setArg(4, lik_);
  likelihoods_.setArg(5, overlap_);
  likelihoods_.setArg(6, stats_);
  q.enqueueNDRangeKernel(likelihoods_, ::cl::NullRange, ::cl::NDRange(tiles), ::cl::NullRange);

  // 3. The prior's row counts, then one work-item per pixel.
  row_counts_.resize(ctx_.context(), w, h);
  if (params_.prior_radius > 0) {
    count_rows_.setArg(0, categories.buffer());
    count_rows_.setArg(1, w);
    count_rows_.setArg(2, h);
    count_rows_.setArg(3, row_counts_.buffer());
    ctx_.run_2d(count_rows_, w, h);
  }
  cost_kernel_.setArg(0, in.colour->buffer());
  cost_kernel_.setArg(1, in.real_depth_mm->buffer());
  cost_kernel_.setArg(2, in.virtual_depth_mm->buffer());
  cost_kernel_.setArg(3, categories.buffer());
  cost_kernel_.setArg(4, w);
  cost_kernel_.setArg(5, h);
  cost_kernel_.setArg(6, tiles_x);
  cost_kernel_.setArg(7, tiles_y);
  cost_kernel_.setArg(8, lik_);
  cost_kernel_.setArg(9, overlap_);
  cost_kernel_.setArg(10, stats_);
  cost_kernel_.setArg(11, row_counts_.buffer());
  cost_kernel_.setArg(12, cost_.buffer());
  cost_kernel_.setArg(13, softness_.buffer());
  ctx_.run_2d(cost_kernel_, w, h);
}

bool CvfLocalHistogram::colour_models_valid() {
  cl_int valid = 0;
  ctx_.queue().enqueueReadBuffer(stats_, CL_TRUE, 0, sizeof(valid), &valid);
  return valid != 0;
}

}  // namespace probeless::occlusion
