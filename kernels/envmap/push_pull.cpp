#include "kernels/envmap/push_pull.hpp"

#include <array>
#include <stdexcept>

#include "kernels/envmap/push_pull_cl.hpp"

namespace probeless::envmap {

PushPull::PushPull(ComputeContext& ctx)
    : ctx_(ctx),
      pull_(ctx.kernel("push_pull", cl_source::push_pull, {}, "pull")),
      push_(ctx.kernel("push_pull", cl_source::push_pull, {}, "push")),
      seed_(ctx.kernel("push_pull", cl_source::push_pull, {}, "seed_borders")) {}

void PushPull::resize_levels(int n) {
  if (n == face_size_) return;
  levels_.clear();
  for (int m = n; m > 1;) {
    m = (m + 1) / 2;
    levels_.emplace_back(ctx_.context(), m, 6 * m);
  }
  face_size_ = n;
}

void PushPull::pull_push(DeviceImage<float, 4>& texels, int face_mask) {
  const auto run = [&](::cl::Kernel& k, const DeviceImage<float, 4>& fine, bool fine_is_texels,
                       const DeviceImage<float, 4>& coarse, int work_size) {
    k.setArg(0, fine.buffer());
    k.setArg(1, fine.width());
    k.setArg(2, fine_is_texels ? 1 : 0);
    k.setArg(3, coarse.buffer());
    k.setArg(4, coarse.width());
    k.setArg(5, face_mask);
    ctx_.run_2d(k, work_size, 6 * work_size);
  };
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    const DeviceImage<float, 4>& fine = k == 0 ? texels : levels_[k - 1];
    run(pull_, fine, k == 0, levels_[k], levels_[k].width());
  }
  for (std::size_t k = levels_.size(); k-- > 0;) {
    const DeviceImage<float, 4>& fine = k == 0 ? texels : levels_[k - 1];
    run(push_, fine, k == 0, levels_[k], fine.width());
  }
}

int PushPull::fill(DeviceImage<float, 4>& texels) {
  const int n = texels.width();
  if (texels.height() != 6 * n) throw std::invalid_argument("PushPull: texels must be n x 6n");
  if (n <= 1) return 0;  // nothing coarser to pull into
  resize_levels(n);
  pull_push(texels, 0x3F);

  std::array<cl_float4, 6> top{};
  ctx_.queue().enqueueReadBuffer(levels_.back().buffer(), CL_TRUE, 0, sizeof(top), top.data());
  int have = 0;
  for (int f = 0; f < 6; ++f)
    if (top[f].s[3] > 0) have |= 1 << f;
  const int observed = have;
  for (int pass = 0; pass < 3 && have != 0 && have != 0x3F; ++pass) {
    int reachable = 0;
    for (int f = 0; f < 6; ++f)
      if (!(have >> f & 1) && (adjacent_faces(f) & have)) reachable |= 1 << f;
    seed_.setArg(0, texels.buffer());
    seed_.setArg(1, n);
    seed_.setArg(2, reachable);
    seed_.setArg(3, have);
    ctx_.run_2d(seed_, n, 24);
    pull_push(texels, reachable);
    have |= reachable;
  }
  return observed;
}

}  // namespace probeless::envmap
