#include "kernels/occlusion/baselines/bilateral_matte.hpp"

#include "kernels/occlusion/baselines/bilateral_matte_cl.hpp"
#include "kernels/occlusion/common/cvf_kernel_args.hpp"

namespace probeless::occlusion {

BilateralMatte::BilateralMatte(ComputeContext& ctx, const BilateralMatteParams& params)
    : ctx_(ctx),
      params_(params),
      categoriser_(ctx, params.categorise),
      kernel_(ctx.kernel("bilateral_matte", cl_source::bilateral_matte, "", "bilateral_matte")) {}

void BilateralMatte::process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  check_inputs(in, name());
  const int w = in.width(), h = in.height();
  alpha.resize(ctx_.context(), w, h);
  if (alpha.empty()) return;
  categoriser_.run(in);
  const float ks = -0.5F / (params_.sigma_space_px * params_.sigma_space_px);
  const float kc = -0.5F / (params_.sigma_colour * params_.sigma_colour) / (255.0F * 255.0F);
  set_args(kernel_, in.colour->buffer(), categoriser_.categories().buffer(), w, h, params_.radius,
           ks, kc, alpha.buffer());
  run_pixels(ctx_, kernel_, w, h);
}

}  // namespace probeless::occlusion
