#include "kernels/occlusion/common/guided_filter.hpp"

#include <fmt/format.h>

#include "kernels/occlusion/common/guided_filter_cl.hpp"

namespace probeless::occlusion {
namespace {

std::string build_options(int radius, GuidedFilter::Output output) {
  return fmt::format("-DRADIUS={} -DTILE_W={} -DTILE_H={} -DOUTPUT_MODE={}", radius,
                     GuidedFilter::kTileWidth, GuidedFilter::kTileHeight, int(output));
}

}  // namespace

GuidedFilter::GuidedFilter(ComputeContext& ctx, int radius, float eps, Output output)
    : ctx_(ctx), radius_(radius), eps_(eps), output_(output) {
  if (radius < 0) throw std::invalid_argument("GuidedFilter: negative radius");
  const auto opts = build_options(radius, output);
  coefficients_ = ctx.kernel("guided_filter", cl_source::guided_filter, opts, "gf_coefficients");
  apply_ = ctx.kernel("guided_filter", cl_source::guided_filter, opts, "gf_mean_apply");
}

void GuidedFilter::enqueue(::cl::Kernel& k, int w, int h) {
  const std::size_t gx = round_up(static_cast<std::size_t>(w), kTileWidth);
  const std::size_t gy = (static_cast<std::size_t>(h) + kTileHeight - 1) / kTileHeight;
  ctx_.queue().enqueueNDRangeKernel(k, ::cl::NullRange, ::cl::NDRange(gx, gy),
                                    ::cl::NDRange(kTileWidth, 1));
}

void GuidedFilter::coefficients(const DeviceImageF4& guide_p, DeviceImageF4& ab) {
  const int w = guide_p.width(), h = guide_p.height();
  ab.resize(ctx_.context(), w, h);
  if (guide_p.empty()) return;
  coefficients_.setArg(0, guide_p.buffer());
  coefficients_.setArg(1, ab.buffer());
  coefficients_.setArg(2, w);
  coefficients_.setArg(3, h);
  coefficients_.setArg(4, eps_);
  enqueue(coefficients_, w, h);
}

void GuidedFilter::apply(const DeviceImageF4& ab, DeviceImageF4* mean_ab,
                         const DeviceImageF4* guide_p, const DeviceImageF* virtual_mm,
                         DeviceImageF* out) {
  const int w = ab.width(), h = ab.height();
  if (ab.empty()) return;
  // Unused arguments still need a buffer; `ab` stands in for them.
  const ::cl::Buffer& any = ab.buffer();
  if (output_ == Output::MeanCoefficients) {
    if (!mean_ab) throw std::invalid_argument("GuidedFilter: no mean_ab output");
    mean_ab->resize(ctx_.context(), w, h);
  } else {
    if (!out || !guide_p || !guide_p->same_size(ab))
      throw std::invalid_argument("GuidedFilter: output or guide missing");
    if (output_ != Output::Raw && (!virtual_mm || !virtual_mm->same_size(ab)))
      throw std::invalid_argument("GuidedFilter: virtual depth missing");
    out->resize(ctx_.context(), w, h);
  }
  apply_.setArg(0, ab.buffer());
  apply_.setArg(1, w);
  apply_.setArg(2, h);
  apply_.setArg(3, mean_ab ? mean_ab->buffer() : any);
  apply_.setArg(4, guide_p ? guide_p->buffer() : any);
  apply_.setArg(5, virtual_mm ? virtual_mm->buffer() : any);
  apply_.setArg(6, out ? out->buffer() : any);
  enqueue(apply_, w, h);
}

}  // namespace probeless::occlusion
