#include "kernels/occlusion/baselines/guided_matte.hpp"

#include "kernels/occlusion/baselines/guided_matte_cl.hpp"
#include "kernels/occlusion/common/cvf_kernel_args.hpp"

namespace probeless::occlusion {

GuidedMatte::GuidedMatte(ComputeContext& ctx, const GuidedMatteParams& params)
    : ctx_(ctx),
      categoriser_(ctx, params.categorise),
      filter_(ctx, params.filter.radius, params.filter.eps, GuidedFilter::Output::Visibility),
      pack_(ctx.kernel("guided_matte", cl_source::guided_matte, "", "guided_matte_pack")) {
  if (params.filter.subsample != 1)
    throw std::invalid_argument("guided: the baseline runs the exact filter (subsample 1)");
}

void GuidedMatte::process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  check_inputs(in, name());
  const int w = in.width(), h = in.height();
  alpha.resize(ctx_.context(), w, h);
  packed_.resize(ctx_.context(), w, h);
  if (alpha.empty()) return;
  categoriser_.run(in);
  set_args(pack_, in.colour->buffer(), categoriser_.categories().buffer(), w, h, packed_.buffer());
  run_pixels(ctx_, pack_, w, h);
  filter_.coefficients(packed_, ab_);
  filter_.apply(ab_, nullptr, &packed_, in.virtual_depth_mm, &alpha);
}

}  // namespace probeless::occlusion
