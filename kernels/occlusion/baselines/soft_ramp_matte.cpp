#include "kernels/occlusion/baselines/soft_ramp_matte.hpp"

#include "kernels/occlusion/baselines/soft_ramp_matte_cl.hpp"
#include "kernels/occlusion/common/cvf_kernel_args.hpp"

namespace probeless::occlusion {

SoftRampMatte::SoftRampMatte(ComputeContext& ctx, const SoftRampParams& params)
    : ctx_(ctx),
      params_(params),
      kernel_(ctx.kernel("soft_ramp_matte", cl_source::soft_ramp_matte, "", "soft_ramp_matte")) {}

void SoftRampMatte::process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  check_inputs(in, name());
  const int w = in.width(), h = in.height();
  alpha.resize(ctx_.context(), w, h);
  if (alpha.empty()) return;
  set_args(kernel_, in.real_depth_mm->buffer(), in.virtual_depth_mm->buffer(), w, h,
           params_.smoothing_radius, params_.relative_half_width, alpha.buffer());
  run_pixels(ctx_, kernel_, w, h);
}

}  // namespace probeless::occlusion
