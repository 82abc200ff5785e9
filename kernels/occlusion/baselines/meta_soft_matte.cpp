#include "kernels/occlusion/baselines/meta_soft_matte.hpp"

#include "kernels/occlusion/baselines/meta_soft_matte_cl.hpp"
#include "kernels/occlusion/common/cvf_kernel_args.hpp"

namespace probeless::occlusion {

MetaSoftMatte::MetaSoftMatte(ComputeContext& ctx, const MetaSoftParams& params)
    : ctx_(ctx),
      params_(params),
      kernel_(ctx.kernel("meta_soft_matte", cl_source::meta_soft_matte, "", "meta_soft_matte")) {}

void MetaSoftMatte::process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  check_inputs(in, name());
  const int w = in.width(), h = in.height();
  alpha.resize(ctx_.context(), w, h);
  if (alpha.empty()) return;
  set_args(kernel_, in.real_depth_mm->buffer(), in.virtual_depth_mm->buffer(), w, h, params_.radius,
           params_.relative_range, params_.blend_threshold, params_.foreground_level,
           params_.background_level, alpha.buffer());
  run_pixels(ctx_, kernel_, w, h);
}

}  // namespace probeless::occlusion
