#include "kernels/undistort/undistort.hpp"

#include <stdexcept>
#include <string>

#include "kernels/undistort/undistort_cl.hpp"

namespace probeless {

Undistort::Undistort(ComputeContext& ctx, const UndistortMap& map)
    : ctx_(ctx),
      map_(ctx, map.source),
      colour_(ctx.kernel("undistort", cl_source::undistort, "", "undistort_rgb8")),
      depth_(ctx.kernel("undistort", cl_source::undistort, "", "undistort_depth")) {}

template <typename T, int C>
void Undistort::run(::cl::Kernel& kernel, const DeviceImage<T, C>& in, DeviceImage<T, C>& out) {
  if (!in.same_size(map_))
    throw std::invalid_argument("Undistort: a " + std::to_string(in.width()) + " x " +
                                std::to_string(in.height()) + " frame, but the colour camera is " +
                                std::to_string(map_.width()) + " x " +
                                std::to_string(map_.height()));
  out.resize(ctx_.context(), map_.width(), map_.height());
  if (out.empty()) return;
  kernel.setArg(0, in.buffer());
  kernel.setArg(1, out.buffer());
  kernel.setArg(2, map_.buffer());
  kernel.setArg(3, map_.width());
  kernel.setArg(4, map_.height());
  ctx_.run_2d(kernel, map_.width(), map_.height());
}

void Undistort::colour(const DeviceImageRGB8& in, DeviceImageRGB8& out) {
  run(colour_, in, out);
}

void Undistort::depth(const DeviceDepthImage& in, DeviceDepthImage& out) {
  run(depth_, in, out);
}

}  // namespace probeless
