#include "kernels/occlusion/foreground/foreground_estimate.hpp"

#include <stdexcept>
#include <string>

#include "kernels/occlusion/foreground/foreground_estimate_cl.hpp"

namespace probeless::occlusion {

ForegroundEstimate::ForegroundEstimate(ComputeContext& ctx, const ForegroundEstimateParams& params)
    : ctx_(ctx), params_((validate(params), params)) {
  kernel_ =
      ctx.kernel("foreground_estimate", cl_source::foreground_estimate, "", "foreground_estimate");
  auto table = decode_table(params_.gamma);
  decode_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                         table.size() * sizeof(float), table.data());
}

void ForegroundEstimate::process(const DeviceImageRGB8& colour,
                                 const DeviceImageF& virtual_depth_mm,
                                 const DeviceImageF& visibility, DeviceImageRGB8& out,
                                 const std::optional<PixelRect>& objects) {
  if (!virtual_depth_mm.same_size(colour) || !visibility.same_size(colour))
    throw std::invalid_argument("foreground estimate: colour (" + std::to_string(colour.width()) +
                                "x" + std::to_string(colour.height()) + "), virtual depth (" +
                                std::to_string(virtual_depth_mm.width()) + "x" +
                                std::to_string(virtual_depth_mm.height()) + ") and matte (" +
                                std::to_string(visibility.width()) + "x" +
                                std::to_string(visibility.height()) + ") differ in size");
  const int w = colour.width(), h = colour.height();
  out.resize(ctx_.context(), w, h);
  if (out.empty()) return;
  int a = 0;
  kernel_.setArg(a++, colour.buffer());
  kernel_.setArg(a++, virtual_depth_mm.buffer());
  kernel_.setArg(a++, visibility.buffer());
  kernel_.setArg(a++, decode_);
  kernel_.setArg(a++, out.buffer());
  kernel_.setArg(a++, w);
  kernel_.setArg(a++, h);
  kernel_.setArg(a++, params_.radius_px);
  kernel_.setArg(a++, params_.confident);
  kernel_.setArg(a++, 1.0F - params_.confident);
  kernel_.setArg(a++, static_cast<float>(1.0 / params_.gamma));
  const PixelRect whole = PixelRect::whole(w, h);
  const PixelRect rect = objects ? intersect(*objects, whole) : whole;
  if (rect == whole) {
    ctx_.run_2d(kernel_, w, h);
    return;
  }
  ctx_.queue().enqueueCopyBuffer(colour.buffer(), out.buffer(), 0, 0, colour.size_bytes());
  ctx_.run_2d(kernel_, rect);
}

}  // namespace probeless::occlusion
