#include "kernels/envmap/keyframe_set.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>

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
  if (config_.max_keyframes < 1)
    throw std::invalid_argument("KeyframeSet: max_keyframes must be >= 1");
}

const Keyframe* KeyframeSet::find(int id) const {
  for (const auto& k : keyframes_)
    if (k->id == id) return k.get();
  return nullptr;
}

Keyframe* KeyframeSet::find(int id) {
  return const_cast<Keyframe*>(std::as_const(*this).find(id));
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
  ++captures_;
  Keyframe* near = nearest_mutable(position);
  Keyframe* chosen = near;
  if (!near || (near->position - position).norm() > config_.new_keyframe_distance_m) {
    const int n = config_.face_size;
    auto k = std::make_unique<Keyframe>();
    k->id = next_id_++;
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
    if (static_cast<int>(keyframes_.size()) > config_.max_keyframes)
      drop_farthest_from(position, *chosen);
  }
  chosen->last_capture = captures_;
  if (active_ != chosen->id) {
    if (Keyframe* previous = find(active_)) zero(ctx_, previous->pending);
    active_ = chosen->id;
  }
  return *chosen;
}

// The rig is where it will capture next: the keyframe farthest from it is the one least likely
// to be updated again or to be the nearest to anything it lights. Seen from a drifting tracker
// the old keyframes are the far ones, so the set follows the drift instead of piling it up.
void KeyframeSet::drop_farthest_from(const Eigen::Vector3d& position, const Keyframe& kept) {
  // Equally far: within 1 mm, below what the tracked poses resolve.
  constexpr double kSameDistanceM = 1e-3;
  auto victim = keyframes_.end();
  double victim_d = -1;
  for (auto it = keyframes_.begin(); it != keyframes_.end(); ++it) {
    if (it->get() == &kept) continue;
    const double d = ((*it)->position - position).norm();
    if (victim == keyframes_.end() || d > victim_d + kSameDistanceM ||
        (d >= victim_d - kSameDistanceM && (*it)->last_capture < (*victim)->last_capture)) {
      victim = it;
      victim_d = d;
    }
  }
  if (victim == keyframes_.end()) return;
  if ((*victim)->id == active_) active_ = -1;
  // The seed kernel above may read the victim's texels (it was the nearest when the cap is 1):
  // drain the queue before its buffers go. A new keyframe is made every few seconds at most.
  ctx_.queue().finish();
  keyframes_.erase(victim);
  ++dropped_;
}

}  // namespace probeless::envmap
