#include "kernels/envmap/keyframe_set.hpp"

#include <limits>
#include <stdexcept>

#include "kernels/envmap/keyframe_seed_cl.hpp"

namespace probeless::envmap {

namespace {

void zero(ComputeContext& ctx, DeviceImage<float, 4>& image) {
  if (!image.empty())
    ctx.queue().enqueueFillBuffer(image.buffer(), cl_float4{{0, 0, 0, 0}}, 0, image.size_bytes());
}

}  // namespace

KeyframeSet::KeyframeSet(ComputeContext& ctx, const KeyframeConfig& config)
    : ctx_(ctx),
      config_(config),
      seed_(ctx.kernel("keyframe_seed", cl_source::keyframe_seed, {}, "seed_keyframe")) {
  if (config_.face_size < 1) throw std::invalid_argument("KeyframeSet: face_size must be >= 1");
  if (!(config_.new_keyframe_distance_m > 0))
    throw std::invalid_argument("KeyframeSet: new_keyframe_distance_m must be positive");
}

Keyframe* KeyframeSet::nearest_mutable(const Eigen::Vector3d& position) const {
  Keyframe* best = nullptr;
  double best_d = std::numeric_limits<double>::infinity();
  for (const auto& k : keyframes_) {
    const double d = (k->position - position).norm();
    if (d < best_d) {
      best_d = d;
      best = k.get();
    }
  }
  return best;
}

const Keyframe* KeyframeSet::nearest(const Eigen::Vector3d& position) const {
  return nearest_mutable(position);
}

Keyframe& KeyframeSet::for_capture(const Eigen::Vector3d& position) {
  Keyframe* near = nearest_mutable(position);
  Keyframe* chosen = near;
  if (!near || (near->position - position).norm() > config_.new_keyframe_distance_m) {
    const int n = config_.face_size;
    auto k = std::make_unique<Keyframe>();
    k->id = static_cast<int>(keyframes_.size());
    k->position = position;
    k->texels = DeviceImage<float, 4>(ctx_, n, 6 * n);
    k->pending = DeviceImage<float, 4>(ctx_, n, 6 * n);
    zero(ctx_, k->pending);
    if (near) {
      const int count = 6 * n * n;
      seed_.setArg(0, near->texels.buffer());
      seed_.setArg(1, k->texels.buffer());
      seed_.setArg(2, count);
      ctx_.queue().enqueueNDRangeKernel(
          seed_, ::cl::NullRange, ::cl::NDRange(round_up(static_cast<std::size_t>(count), 64)),
          ::cl::NDRange(64));
    } else {
      zero(ctx_, k->texels);
    }
    keyframes_.push_back(std::move(k));
    chosen = keyframes_.back().get();
  }
  if (active_ != chosen->id) {
    if (active_ >= 0) zero(ctx_, keyframes_[static_cast<std::size_t>(active_)]->pending);
    active_ = chosen->id;
  }
  return *chosen;
}

}  // namespace probeless::envmap
