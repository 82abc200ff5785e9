#include "kernels/occlusion/cvf/near_occluder.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "kernels/occlusion/cvf/near_occluder_cl.hpp"

namespace probeless::occlusion {
namespace {

const NearOccluderParams& checked(const NearOccluderParams& p) {
  if (p.bins_per_channel < 1 || p.bins_per_channel > 8)
    throw std::invalid_argument("near occluder: bins per channel must be 1..8");
  if (p.tile_px < 1) throw std::invalid_argument("near occluder: tile_px must be >= 1");
  return p;
}

}  // namespace

NearOccluder::NearOccluder(ComputeContext& ctx, const NearOccluderParams& params)
    : ctx_(ctx),
      params_(checked(params)),
      bins_(params.bins_per_channel * params.bins_per_channel * params.bins_per_channel) {
  const std::string options = "-DBINS=" + std::to_string(params_.bins_per_channel) +
                              " -DTILE=" + std::to_string(params_.tile_px);
  histograms_ =
      ctx.kernel("near_occluder", cl_source::near_occluder, options, "near_occluder_histograms");
  background_ =
      ctx.kernel("near_occluder", cl_source::near_occluder, options, "near_occluder_background");
  apply_ = ctx.kernel("near_occluder", cl_source::near_occluder, options, "near_occluder_apply");
}

void NearOccluder::process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  const int w = in.width(), h = in.height();
  if (w * h == 0) return;
  const int tiles_x = (w + params_.tile_px - 1) / params_.tile_px;
  const int tiles = tiles_x * ((h + params_.tile_px - 1) / params_.tile_px);
  const std::size_t words = 2 * std::size_t(bins_) + 2 + std::size_t(tiles) * (bins_ + 1);
  if (words != hist_words_) {
    hist_ = ::cl::Buffer(ctx_.context(), CL_MEM_READ_WRITE, words * sizeof(cl_uint));
    hist_words_ = words;
  }
  auto& q = ctx_.queue();
  q.enqueueFillBuffer(hist_, cl_uint{0}, 0, words * sizeof(cl_uint));
  int a = 0;
  histograms_.setArg(a++, in.colour->buffer());
  histograms_.setArg(a++, in.real_depth_mm->buffer());
  histograms_.setArg(a++, in.virtual_depth_mm->buffer());
  histograms_.setArg(a++, w);
  histograms_.setArg(a++, h);
  histograms_.setArg(a++, tiles_x);
  histograms_.setArg(a++, params_.depth_tolerance_mm);
  histograms_.setArg(a++, hist_);
  ctx_.run_2d(histograms_, w, h);
  q_.resize(ctx_.context(), w, h);
  a = 0;
  background_.setArg(a++, in.colour->buffer());
  background_.setArg(a++, in.real_depth_mm->buffer());
  background_.setArg(a++, in.virtual_depth_mm->buffer());
  background_.setArg(a++, w);
  background_.setArg(a++, h);
  background_.setArg(a++, tiles_x);
  background_.setArg(a++, static_cast<cl_uint>(std::max(1, params_.min_samples)));
  background_.setArg(a++, hist_);
  background_.setArg(a++, q_.buffer());
  ctx_.run_2d(background_, w, h);
  a = 0;
  apply_.setArg(a++, in.real_depth_mm->buffer());
  apply_.setArg(a++, q_.buffer());
  apply_.setArg(a++, w);
  apply_.setArg(a++, h);
  apply_.setArg(a++, std::max(0, params_.prior_radius));
  apply_.setArg(a++, alpha.buffer());
  ctx_.run_2d(apply_, w, h);
}

}  // namespace probeless::occlusion
