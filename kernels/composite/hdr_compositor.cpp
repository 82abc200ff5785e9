#include "kernels/composite/hdr_compositor.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "kernels/composite/hdr_compositor_cl.hpp"

namespace probeless {

HdrCompositor::HdrCompositor(ComputeContext& ctx) : ctx_(ctx) {
  use_gamma(CameraResponse{}.gamma);  // build for the usual curve before the first frame
}

void HdrCompositor::use_gamma(double gamma) {
  if (curve_ && curve_->gamma() == gamma) return;
  CameraCurve curve(gamma);  // validates before anything is replaced
  if (!curve_ || curve_->steps() != curve.steps())
    kernel_ = ctx_.kernel("hdr_compositor", cl_source::hdr_compositor,
                          "-DSTEPS=" + std::to_string(curve.steps()), "hdr_composite");
  // CL_MEM_COPY_HOST_PTR copies at creation: nothing on the queue reads host memory later,
  // and a gamma change (a configuration event) costs three small allocations.
  const auto table = [this](const auto& host) {
    return ::cl::Buffer(ctx_.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                        host.size() * sizeof(host[0]),
                        const_cast<void*>(static_cast<const void*>(host.data())));
  };
  decode_ = table(curve.decode_table());
  thresholds_ = table(curve.thresholds());
  entries_ = table(curve.entries());
  curve_ = std::move(curve);
}

void HdrCompositor::process(const DeviceImageRGB8& real_rgb, const DeviceImage<float, 4>& layer,
                            const DeviceImageF& matte, const CameraResponse& camera,
                            DeviceImageRGB8& out, const std::optional<PixelRect>& objects) {
  if (!layer.same_size(real_rgb) || !matte.same_size(real_rgb))
    throw std::invalid_argument(
        "HdrCompositor: real (" + std::to_string(real_rgb.width()) + "x" +
        std::to_string(real_rgb.height()) + "), layer (" + std::to_string(layer.width()) + "x" +
        std::to_string(layer.height()) + ") and matte (" + std::to_string(matte.width()) + "x" +
        std::to_string(matte.height()) + ") differ in size");
  const ExposureFactors f = exposure_factors(camera);  // validates
  use_gamma(camera.gamma);
  out.resize(ctx_.context(), real_rgb.width(), real_rgb.height());
  if (out.empty()) return;
  // The frame as it is, then the kernel rewrites the pixels with a virtual layer (matte > 0):
  // a device-side memcpy is cheaper than any kernel copying 3-byte pixels.
  ctx_.queue().enqueueCopyBuffer(real_rgb.buffer(), out.buffer(), 0, 0, real_rgb.size_bytes());
  const int w = out.width();
  const PixelRect whole = PixelRect::whole(w, out.height());
  const PixelRect rows = objects ? intersect(*objects, whole) : whole;
  if (rows.empty()) return;
  const int begin = rows.y0 * w, end = rows.y1 * w;  // flattened: whole rows
  int a = 0;
  kernel_.setArg(a++, real_rgb.buffer());
  kernel_.setArg(a++, layer.buffer());
  kernel_.setArg(a++, matte.buffer());
  kernel_.setArg(a++, out.buffer());
  kernel_.setArg(a++, begin);
  kernel_.setArg(a++, end);
  kernel_.setArg(a++, cl_float4{{f.e[0], f.e[1], f.e[2], 0.0F}});
  kernel_.setArg(a++, cl_float4{{f.inverse_e[0], f.inverse_e[1], f.inverse_e[2], 0.0F}});
  kernel_.setArg(a++, decode_);
  kernel_.setArg(a++, thresholds_);
  kernel_.setArg(a++, entries_);
  kernel_.setArg(a++, curve_->index_base());
  kernel_.setArg(a++, curve_->index_last());
  // One dimension over the flattened frame, work-groups as large as run_2d's.
  const std::size_t items =
      (static_cast<std::size_t>(end - begin) + kPixelsPerItem - 1) / kPixelsPerItem;
  const std::size_t local = ctx_.local_2d()[0] * ctx_.local_2d()[1];
  ctx_.queue().enqueueNDRangeKernel(kernel_, ::cl::NullRange,
                                    ::cl::NDRange((items + local - 1) / local * local),
                                    ::cl::NDRange(local));
}

}  // namespace probeless
