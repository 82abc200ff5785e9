#include "kernels/tracking/dense_tracker.hpp"

#include <stdexcept>

// SCAFFOLD: the interface the service and the lab build against while the tracker is written;
// it reports the first pose for every frame. Replaced by the Kerl et al. tracker.
namespace probeless::tracking {

const char* to_string(TrackingState state) {
  switch (state) {
    case TrackingState::Off:
      return "off";
    case TrackingState::Tracking:
      return "tracking";
    case TrackingState::Lost:
      return "lost";
    case TrackingState::Relocalising:
      return "relocalising";
  }
  return "?";
}

struct DenseTracker::Impl {
  ComputeContext* ctx = nullptr;
  PinholeIntrinsics camera;
  DenseTrackerParams params;
  Pose origin;
  TrackingState state = TrackingState::Off;
};

DenseTracker::DenseTracker(ComputeContext* ctx, const PinholeIntrinsics& camera,
                           DenseTrackerParams params)
    : impl_(std::make_unique<Impl>()) {
  impl_->ctx = ctx;
  impl_->camera = camera;
  impl_->params = params;
}

DenseTracker::~DenseTracker() = default;

TrackResult DenseTracker::track(const ImageRGB8& colour, const DepthImage& depth_mm, TimestampNs) {
  const auto& k = impl_->camera;
  if (colour.width() != k.width || colour.height() != k.height || depth_mm.width() != k.width ||
      depth_mm.height() != k.height)
    throw std::invalid_argument("tracking: frame size differs from the colour camera's");
  impl_->state = TrackingState::Tracking;
  TrackResult r;
  r.state = impl_->state;
  r.T_world_camera = impl_->origin;
  r.inlier_fraction = 1.0;
  r.keyframes = 1;
  return r;
}

void DenseTracker::reset(const Pose& T_world_camera) {
  impl_->origin = T_world_camera;
  impl_->state = TrackingState::Off;
}

TrackingState DenseTracker::state() const {
  return impl_->state;
}
bool DenseTracker::uses_device() const {
  return impl_->ctx != nullptr;
}

}  // namespace probeless::tracking
