#include "kernels/composite/hdr_compositor.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "kernels/composite/hdr_compositor_cl.hpp"

namespace probeless {

HdrCompositor::HdrCompositor(ComputeContext& ctx)
    : ctx_(ctx),
      kernel_(ctx.kernel("hdr_compositor", cl_source::hdr_compositor, "", "hdr_composite")) {
  use_gamma(CameraResponse{}.gamma);  // the tables of the usual curve before the first frame
}

void HdrCompositor::use_gamma(double gamma) {
  if (curve_ && curve_->gamma() == gamma) return;
  CameraCurve curve(gamma);  // validates before anything is replaced
  // CL_MEM_COPY_HOST_PTR copies at creation: nothing on the queue reads host memory later,
  // and a gamma change (a configuration event) costs three small allocations.
  const auto table = [this](const auto& host) {
    return ::cl::Buffer(ctx_.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                        host.size() * sizeof(host[0]),
                        const_cast<void*>(static_cast<const void*>(host.data())));
  };
  decode_ = table(curve.decode_table());
  thresholds_ = table(curve.thresholds());
  index_ = table(curve.index());
  curve_ = std::move(curve);
}

void HdrCompositor::process(const DeviceImageRGB8& real_rgb, const DeviceImage<float, 4>& layer,
                            const DeviceImageF& matte, const CameraResponse& camera,
                            DeviceImageRGB8& out) {
  if (!layer.same_size(real_rgb) || !matte.same_size(real_rgb))
    throw std::invalid_argument(
        "HdrCompositor: real (" + std::to_string(real_rgb.width()) + "x" +
        std::to_string(real_rgb.height()) + "), layer (" + std::to_string(layer.width()) + "x" +
        std::to_string(layer.height()) + ") and matte (" + std::to_string(matte.width()) + "x" +
        std::to_string(matte.height()) + ") differ in size");
  const ExposureFactors f = exposure_factors(camera);  // validates
  use_gamma(camera.gamma);
  const int w = real_rgb.width(), h = real_rgb.height();
  out.resize(ctx_.context(), w, h);
  if (out.empty()) return;
  int a = 0;
  kernel_.setArg(a++, real_rgb.buffer());
  kernel_.setArg(a++, layer.buffer());
  kernel_.setArg(a++, matte.buffer());
  kernel_.setArg(a++, out.buffer());
  kernel_.setArg(a++, w);
  kernel_.setArg(a++, h);
  kernel_.setArg(a++, cl_float4{{f.e[0], f.e[1], f.e[2], 0.0F}});
  kernel_.setArg(a++, cl_float4{{f.inverse_e[0], f.inverse_e[1], f.inverse_e[2], 0.0F}});
  kernel_.setArg(a++, decode_);
  kernel_.setArg(a++, thresholds_);
  kernel_.setArg(a++, index_);
  kernel_.setArg(a++, curve_->steps());
  ctx_.run_2d(kernel_, (w + kPixelsPerItem - 1) / kPixelsPerItem, h);
}

}  // namespace probeless
