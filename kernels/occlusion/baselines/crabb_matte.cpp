#include "kernels/occlusion/baselines/crabb_matte.hpp"

#include "kernels/occlusion/baselines/crabb_matte_cl.hpp"
#include "kernels/occlusion/common/cvf_kernel_args.hpp"

namespace probeless::occlusion {

CrabbMatte::CrabbMatte(ComputeContext& ctx)
    : ctx_(ctx),
      mean_(ctx.kernel("crabb_matte", cl_source::crabb_matte, "", "crabb_mean")),
      matte_(ctx.kernel("crabb_matte", cl_source::crabb_matte, "", "crabb_matte")),
      stats_(ctx.context(), CL_MEM_READ_WRITE, 2 * sizeof(float)) {}

void CrabbMatte::process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  check_inputs(in, name());
  const int w = in.width(), h = in.height();
  alpha.resize(ctx_.context(), w, h);
  if (alpha.empty()) return;
  set_args(mean_, in.virtual_depth_mm->buffer(), w * h, stats_);
  ctx_.queue().enqueueNDRangeKernel(mean_, ::cl::NullRange, ::cl::NDRange(256), ::cl::NDRange(256));
  set_args(matte_, in.real_depth_mm->buffer(), in.virtual_depth_mm->buffer(), stats_, w, h,
           alpha.buffer());
  run_pixels(ctx_, matte_, w, h);
}

}  // namespace probeless::occlusion
