#pragma once
// Helpers of the occlusion stages: set_args(kernel, a, b, c) sets arguments 0, 1, 2, ...;
// run_pixels() enqueues a per-pixel 2D kernel in large work-groups.
#include <CL/opencl.hpp>
#include <algorithm>
#include <utility>

#include "kernels/runtime/compute_context.hpp"

namespace probeless::occlusion {

// Sets arguments first, first + 1, ...
template <typename... Args>
void set_args_from(::cl::Kernel& kernel, cl_uint first, Args&&... args) {
  cl_uint index = first;
  (kernel.setArg(index++, std::forward<Args>(args)), ...);
}

template <typename... Args>
void set_args(::cl::Kernel& kernel, Args&&... args) {
  cl_uint index = 0;
  (kernel.setArg(index++, std::forward<Args>(args)), ...);
}

// Per-pixel kernels (bounds-checked) over w x h in work-groups of kPixelGroupW x
// kPixelGroupH: on PoCL every work-group costs a few microseconds of scheduling, and the
// runtime's default 16 x 8 groups made the cheap kernels cost 1-4 ms each at 640 x 480
// (docs/occlusion.md "Speed"). On a GPU the groups stay within the usual limits.
inline constexpr std::size_t kPixelGroupW = 64;
inline constexpr std::size_t kPixelGroupH = 4;

inline void run_pixels(ComputeContext& ctx, const ::cl::Kernel& kernel, int w, int h) {
  if (w <= 0 || h <= 0) return;
  const std::size_t max = std::max<std::size_t>(1, ctx.info().max_work_group_size);
  const std::size_t lw = std::min<std::size_t>(kPixelGroupW, max);
  const std::size_t lh = std::max<std::size_t>(1, std::min<std::size_t>(kPixelGroupH, max / lw));
  ctx.queue().enqueueNDRangeKernel(kernel, ::cl::NullRange,
                                   ::cl::NDRange(round_up(w, lw), round_up(h, lh)),
                                   ::cl::NDRange(lw, lh));
}

}  // namespace probeless::occlusion
