#include "kernels/occlusion/common/categorise.hpp"

#include "kernels/occlusion/common/cvf_categorise_cl.hpp"
#include "kernels/occlusion/common/cvf_kernel_args.hpp"

namespace probeless::occlusion {

Categoriser::Categoriser(ComputeContext& ctx, const CategoriseParams& params)
    : ctx_(ctx), params_(params) {
  if (params.erosion_px < 0) throw std::invalid_argument("categorise: negative erosion");
  auto k = [&](const char* name) {
    return ctx.kernel("cvf_categorise", cl_source::cvf_categorise, depth_tolerance_options(params),
                      name);
  };
  raw_bits_ = k("cvf_raw_bits");
  dilate_rows_ = k("cvf_dilate_rows");
  dilate_cols_ = k("cvf_dilate_cols");
  erode_ = k("cvf_erode");
}

void Categoriser::dilate(const DeviceImageGray8& src, DeviceImageGray8& dst, int radius) {
  const int w = src.width(), h = src.height();
  tmp_.resize(ctx_.context(), w, h);
  dst.resize(ctx_.context(), w, h);
  set_args(dilate_rows_, src.buffer(), tmp_.buffer(), w, h, radius);
  run_pixels(ctx_, dilate_rows_, w, h);
  set_args(dilate_cols_, tmp_.buffer(), dst.buffer(), w, h, radius);
  run_pixels(ctx_, dilate_cols_, w, h);
}

void Categoriser::run(const OcclusionInputs& in) {
  const int w = in.width(), h = in.height();
  for (auto* img : {&raw_, &near_, &categories_, &process_}) img->resize(ctx_.context(), w, h);
  if (raw_.empty()) return;
  set_args(raw_bits_, in.real_depth_mm->buffer(), in.virtual_depth_mm->buffer(), raw_.buffer(), w,
           h, params_.depth_tolerance_mm);
  run_pixels(ctx_, raw_bits_, w, h);
  dilate(raw_, near_, params_.erosion_px);
  set_args(erode_, raw_.buffer(), near_.buffer(), categories_.buffer(), process_.buffer(), w, h);
  run_pixels(ctx_, erode_, w, h);
}

}  // namespace probeless::occlusion
