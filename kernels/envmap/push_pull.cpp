#include "kernels/envmap/push_pull.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "kernels/envmap/push_pull_cl.hpp"

namespace probeless::envmap {

PushPull::PushPull(ComputeContext& ctx)
    : ctx_(ctx),
      pull_push_(ctx.kernel("push_pull", cl_source::push_pull, {}, "pull_push_faces")),
      fill_empty_(ctx.kernel("push_pull", cl_source::push_pull, {}, "fill_empty_faces")),
      face_state_(ctx.context(), CL_MEM_READ_WRITE, 6 * sizeof(cl_int)) {
  // 256 work-items per face: enough to spread a 128 px face's levels, within every device's
  // limit for these kernels.
  const auto max = [&](const ::cl::Kernel& k) {
    return k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(ctx.device());
  };
  local_ = std::min<std::size_t>(256, max(pull_push_));
  local_fill_ = std::min<std::size_t>(256, max(fill_empty_));
}

void PushPull::fill(DeviceImage<float, 4>& texels) {
  const int n = texels.width();
  if (texels.height() != 6 * n) throw std::invalid_argument("PushPull: texels must be n x 6n");
  if (n < 1) return;
  if (n != face_size_) {
    std::size_t texel_count = 0;
    for (int m = n; m > 1;) {
      m = (m + 1) / 2;
      texel_count += 6 * static_cast<std::size_t>(m) * m;
    }
    pyramid_ = ::cl::Buffer(ctx_.context(), CL_MEM_READ_WRITE,
                            std::max<std::size_t>(texel_count, 1) * sizeof(cl_float4));
    face_size_ = n;
  }
  for (::cl::Kernel* k : {&pull_push_, &fill_empty_}) {
    k->setArg(0, texels.buffer());
    k->setArg(1, n);
    k->setArg(2, pyramid_);
    k->setArg(3, face_state_);
  }
  ctx_.queue().enqueueNDRangeKernel(pull_push_, ::cl::NullRange, ::cl::NDRange(6 * local_),
                                    ::cl::NDRange(local_));
  ctx_.queue().enqueueNDRangeKernel(fill_empty_, ::cl::NullRange, ::cl::NDRange(local_fill_),
                                    ::cl::NDRange(local_fill_));
}

int PushPull::observed_faces() {
  std::array<cl_int, 6> state{};
  ctx_.queue().enqueueReadBuffer(face_state_, CL_TRUE, 0, sizeof(state), state.data());
  int mask = 0;
  for (int f = 0; f < 6; ++f)
    if (state[static_cast<std::size_t>(f)] == 2) mask |= 1 << f;
  return mask;
}

}  // namespace probeless::envmap
