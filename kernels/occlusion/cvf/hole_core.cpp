#include "kernels/occlusion/cvf/hole_core.hpp"

#include <stdexcept>
#include <string>

#include "kernels/occlusion/cvf/hole_core_cl.hpp"
#include "kernels/occlusion/cvf/hole_core_reference.hpp"

namespace probeless::occlusion {

HoleCoreFill::HoleCoreFill(ComputeContext& ctx) : ctx_(ctx) {
  const std::string options = "-DNEAR_MM=" + std::to_string(kNearHoleDepthMm);
  rows_ = ctx.kernel("hole_core", cl_source::hole_core, options, "hole_core_rows");
  fill_ = ctx.kernel("hole_core", cl_source::hole_core, options, "hole_core_fill");
}

const DeviceImage<std::uint16_t, 1>& HoleCoreFill::run(const DeviceImage<std::uint16_t, 1>& depth,
                                                       int radius) {
  if (radius < 1) throw std::invalid_argument("hole core: radius must be >= 1");
  const int w = depth.width(), h = depth.height();
  row_cores_.resize(ctx_.context(), w, h);
  filled_.resize(ctx_.context(), w, h);
  if (w * h == 0) return filled_;
  int a = 0;
  rows_.setArg(a++, depth.buffer());
  rows_.setArg(a++, row_cores_.buffer());
  rows_.setArg(a++, w);
  rows_.setArg(a++, h);
  rows_.setArg(a++, radius);
  ctx_.queue().enqueueNDRangeKernel(rows_, ::cl::NullRange, ::cl::NDRange(std::size_t(h)));
  a = 0;
  fill_.setArg(a++, depth.buffer());
  fill_.setArg(a++, row_cores_.buffer());
  fill_.setArg(a++, filled_.buffer());
  fill_.setArg(a++, w);
  fill_.setArg(a++, h);
  fill_.setArg(a++, radius);
  ctx_.queue().enqueueNDRangeKernel(fill_, ::cl::NullRange,
                                    ::cl::NDRange(static_cast<std::size_t>((w + 15) / 16)));
  return filled_;
}

}  // namespace probeless::occlusion
