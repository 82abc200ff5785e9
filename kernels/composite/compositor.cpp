#include "kernels/composite/compositor.hpp"

#include <stdexcept>

#include "kernels/composite/compositor_cl.hpp"

namespace probeless {

Compositor::Compositor(ComputeContext& ctx)
    : ctx_(ctx),
      composite_(ctx.kernel("compositor", cl_source::compositor, "", "composite_rgb8")),
      matte_(ctx.kernel("compositor", cl_source::compositor, "", "matte_gray8")) {}

void Compositor::process(const DeviceImageRGB8& real_rgb, const DeviceImageRGBA8& virtual_rgba,
                         const DeviceImageF& alpha, DeviceImageRGB8& out) {
  if (!virtual_rgba.same_size(real_rgb) || !alpha.same_size(real_rgb))
    throw std::invalid_argument("Compositor: real, virtual and alpha differ in size");
  const int w = real_rgb.width(), h = real_rgb.height();
  out.resize(ctx_.context(), w, h);
  if (out.empty()) return;
  composite_.setArg(0, real_rgb.buffer());
  composite_.setArg(1, virtual_rgba.buffer());
  composite_.setArg(2, alpha.buffer());
  composite_.setArg(3, out.buffer());
  composite_.setArg(4, w);
  composite_.setArg(5, h);
  ctx_.run_2d(composite_, w, h);
}

void Compositor::matte8(const DeviceImageF& alpha, DeviceImageGray8& out) {
  const int w = alpha.width(), h = alpha.height();
  out.resize(ctx_.context(), w, h);
  if (out.empty()) return;
  matte_.setArg(0, alpha.buffer());
  matte_.setArg(1, out.buffer());
  matte_.setArg(2, w);
  matte_.setArg(3, h);
  ctx_.run_2d(matte_, w, h);
}

}  // namespace probeless
