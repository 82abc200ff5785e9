#include "kernels/occlusion/baselines/direct_matte.hpp"

#include "kernels/occlusion/baselines/direct_matte_cl.hpp"

namespace probeless::occlusion {

DirectMatte::DirectMatte(ComputeContext& ctx, UnknownDepth unknown,
                         const CategoriseParams& tolerance)
    : ctx_(ctx),
      unknown_(unknown),
      tolerance_mm_(tolerance.depth_tolerance_mm),
      kernel_(ctx.kernel("direct_matte", cl_source::direct_matte,
                         std::string(unknown == UnknownDepth::Visible ? "-DUNKNOWN_VISIBLE=1"
                                                                      : "-DUNKNOWN_VISIBLE=0") +
                             depth_tolerance_options(tolerance),
                         "direct_matte")) {}

std::string DirectMatte::name() const {
  return unknown_ == UnknownDepth::Visible ? "direct2" : "direct1";
}

void DirectMatte::process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  check_inputs(in, name());
  const int w = in.width(), h = in.height();
  alpha.resize(ctx_.context(), w, h);
  if (alpha.empty()) return;
  kernel_.setArg(0, in.real_depth_mm->buffer());
  kernel_.setArg(1, in.virtual_depth_mm->buffer());
  kernel_.setArg(2, alpha.buffer());
  kernel_.setArg(3, w);
  kernel_.setArg(4, h);
  kernel_.setArg(5, tolerance_mm_);
  ctx_.run_2d(kernel_, w, h);
}

}  // namespace probeless::occlusion
