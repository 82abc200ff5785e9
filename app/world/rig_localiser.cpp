#include "app/world/rig_localiser.hpp"

#include <spdlog/spdlog.h>

#include <stdexcept>

namespace probeless::world {

using tracking::TrackingState;

nlohmann::json LocaliserStatus::to_json() const {
  nlohmann::json j = {{"state", tracking::to_string(state)},
                      {"method", method},
                      {"keyframes", keyframes},
                      {"lost_count", lost_count},
                      {"anchor", {{"kind", anchor}, {"found", anchor_found}}}};
  if (T_world_rig) {
    const Pose& p = *T_world_rig;
    // T_world_rig; q in TUM's order (x, y, z, w), as the trajectory files write it.
    j["pose"] = {{"t", {p.translation.x(), p.translation.y(), p.translation.z()}},
                 {"q", {p.rotation.x(), p.rotation.y(), p.rotation.z(), p.rotation.w()}}};
  } else {
    j["pose"] = nullptr;
  }
  return j;
}

RigLocaliser::RigLocaliser(const TrackingConfig& tracking, const WorldConfig& world,
                           const RigCalibration& calibration, ComputeContext* ctx)
    : config_(tracking), calibration_(calibration), anchor_(world, calibration) {
  if (tracking.method == "dense") {
    tracking::DenseTrackerParams params;
    params.min_depth_m = static_cast<float>(tracking.min_depth_m);
    params.max_depth_m = static_cast<float>(tracking.max_depth_m);
    params.rolling_shutter_readout_s = tracking.rolling_shutter_readout_s;
    // The camera with its distortion: the tracker undistorts its finest level (frames arrive
    // raw; the upload stage undistorts only what the matte and composite see).
    tracker_ = std::make_unique<tracking::DenseTracker>(tracking.device == "opencl" ? ctx : nullptr,
                                                        calibration.rgb, params);
  } else if (tracking.method != "truth" && tracking.method != "off") {
    throw std::invalid_argument("tracking method '" + tracking.method +
                                "' is not one of dense, truth, off");
  }
  status_.method = tracking.method;
  status_.anchor = world.anchor;
}

RigLocaliser::~RigLocaliser() = default;

// The colour camera in the tracker's world: the tracker's first camera (dense), the source's
// world (truth), or the first frame's camera forever (off: a rig that never moves).
std::optional<Pose> RigLocaliser::camera_in_tracker(const RgbdFrame& frame) {
  if (tracker_) {
    // Lost: the marker, when this frame sees it, says where the camera is, globally and
    // without drift; the kept keyframes only find views near their own (and a wrong
    // alignment may pass their test). It is asked before the tracker while lost, and on the
    // frame that loses it. The tracker then starts again there (its keyframes forgotten).
    const auto lost = [](TrackingState s) {
      return s == TrackingState::Lost || s == TrackingState::Relocalising;
    };
    const bool was_lost = lost(status_.state);
    std::optional<Pose> on_marker = was_lost ? anchor_.relocalise(frame) : std::nullopt;
    tracking::TrackResult r;
    if (!on_marker) {
      r = tracker_->track(frame.colour, frame.depth, frame.timestamp_ns);
      if (!was_lost && lost(r.state)) on_marker = anchor_.relocalise(frame);
    }
    if (on_marker) {
      tracker_->reset(*on_marker);
      r = tracker_->track(frame.colour, frame.depth, frame.timestamp_ns);
      spdlog::info("tracking relocalised on the marker at frame {}", frame.sequence);
    }
    status_.state = r.state;
    status_.keyframes = r.keyframes;
    if (r.state != TrackingState::Tracking) return std::nullopt;
    return r.T_world_camera;
  }
  if (config_.method == "off") {
    status_.state = TrackingState::Off;
    return Pose::identity();
  }
  if (frame.truth && frame.truth->rig_pose) {
    status_.state = TrackingState::Tracking;
    return *frame.truth->rig_pose * calibration_.T_rig_rgb;
  }
  if (status_.state != TrackingState::Lost)
    spdlog::warn("tracking: method \"truth\" but frame {} carries no rig pose", frame.sequence);
  status_.state = TrackingState::Lost;
  return std::nullopt;
}

std::optional<Pose> RigLocaliser::locate(const RgbdFrame& frame) {
  const bool was_known = status_.T_world_rig.has_value();
  const std::optional<Pose> T_tracker_camera = camera_in_tracker(frame);
  const std::optional<Pose> T_world_tracker = anchor_.update(frame, T_tracker_camera);
  status_.anchor_found = anchor_.found();
  status_.T_world_rig.reset();
  if (T_tracker_camera && T_world_tracker)
    status_.T_world_rig = *T_world_tracker * *T_tracker_camera * calibration_.T_rig_rgb.inverse();
  if (was_known && !T_tracker_camera) {
    ++status_.lost_count;
    spdlog::warn("tracking lost at frame {}: virtual objects hidden until it returns",
                 frame.sequence);
  }
  return status_.T_world_rig;
}

}  // namespace probeless::world
