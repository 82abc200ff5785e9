#include "kernels/envmap/push_pull.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "kernels/envmap/push_pull_cl.hpp"

namespace probeless::envmap {

PushPull::PushPull(ComputeContext& ctx)
    : ctx_(ctx),
      pull_push_(ctx.kernel("push_pull", cl_source::push_pull, {}, "pull_push_faces")),
      seed_(ctx.kernel("push_pull", cl_source::push_pull, {}, "seed_borders")),
      face_state_(ctx.context(), CL_MEM_READ_WRITE, 6 * sizeof(cl_int)),
      face_target_(ctx.context(), CL_MEM_READ_WRITE, 6 * sizeof(cl_int)) {
  // 256 work-items per face: enough to spread a 128 px face's levels, within every device's
  // limit for this kernel.
  const auto max = pull_push_.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(ctx.device());
  local_ = std::min<std::size_t>(256, max);
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
  const auto pass = [&](int index) {
    pull_push_.setArg(0, texels.buffer());
    pull_push_.setArg(1, n);
    pull_push_.setArg(2, pyramid_);
    pull_push_.setArg(3, face_state_);
    pull_push_.setArg(4, face_target_);
    pull_push_.setArg(5, index);
    ctx_.queue().enqueueNDRangeKernel(pull_push_, ::cl::NullRange, ::cl::NDRange(6 * local_),
                                      ::cl::NDRange(local_));
  };
  pass(0);
  for (int p = 1; p <= 3; ++p) {
    seed_.setArg(0, texels.buffer());
    seed_.setArg(1, n);
    seed_.setArg(2, face_state_);
    seed_.setArg(3, face_target_);
    ctx_.run_2d(seed_, n, 24);
    pass(p);
  }
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
