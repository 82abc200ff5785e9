#include "app/world/world_anchor.hpp"

#include <algorithm>
#include <stdexcept>

#include "app/world/board_detector.hpp"
#include "app/world/marker_worker.hpp"

namespace probeless::world {
namespace {

// A new marker sighting moves the estimate a quarter of the way (then at most max_step_mm):
// an average over ~4 sightings, which keeps the corner noise of one frame (~0.1 px on the
// sim's board) out of the picture while following a real change within a few frames.
constexpr double kBlend = 0.25;

BoardCamera board_camera(const RigCalibration& c) {
  const PinholeIntrinsics& k = c.rgb.intrinsics();
  const BrownDistortion& d = c.rgb.distortion();
  BoardCamera b;
  b.K = {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
  if (!d.is_zero()) b.distortion = {d.k1, d.k2, d.p1, d.p2, d.k3};
  b.width = k.width;
  b.height = k.height;
  return b;
}

}  // namespace

double world_step_m(const Pose& a, const Pose& b, double reach_m) {
  // Where the world's origin is in the tracker's (real) world, before and after.
  const Pose ia = a.inverse(), ib = b.inverse();
  return (ia.translation - ib.translation).norm() +
         ia.rotation.angularDistance(ib.rotation) * reach_m;
}

WorldAnchor::WorldAnchor(const WorldConfig& config, const RigCalibration& calibration)
    : config_(config), calibration_(calibration) {
  floor_.max_tilt_deg = config.floor_max_tilt_deg;
  if (config.anchor == "marker")
    marker_ = std::make_unique<MarkerWorker>(std::make_unique<BoardDetector>(
        parse_board_spec(config.marker), board_camera(calibration)));
  else if (config.anchor != "floor" && config.anchor != "rig")
    throw std::invalid_argument("world anchor '" + config.anchor +
                                "' is not one of marker, floor, rig");
}

WorldAnchor::~WorldAnchor() = default;

std::optional<Pose> WorldAnchor::measure(const RgbdFrame& frame, const Pose& T_tracker_camera) {
  const Pose T_camera_tracker = T_tracker_camera.inverse();
  if (config_.anchor == "rig") {
    // The source's rig pose at the first frame, or the origin: today's fixed rig.
    const Pose T_world_rig =
        frame.truth && frame.truth->rig_pose ? *frame.truth->rig_pose : Pose::identity();
    return T_world_rig * calibration_.T_rig_rgb * T_camera_tracker;
  }
  if (config_.anchor == "floor") {
    const auto floor = find_floor(frame.depth, calibration_.rgb.intrinsics(), floor_);
    if (!floor) return std::nullopt;
    return floor->T_camera_floor.inverse() * T_camera_tracker;
  }
  // The marker: this frame goes to the detector if it is free; what comes back is a sighting
  // of an earlier frame, already related to the tracker's world through that frame's pose.
  marker_->offer(frame.colour, T_tracker_camera);
  const auto sighting = marker_->take();
  if (!sighting) return std::nullopt;
  marker_in_view_ = sighting->found;
  if (!sighting->found) return std::nullopt;
  return sighting->T_world_tracker;
}

std::optional<Pose> WorldAnchor::relocalise(const RgbdFrame& frame) {
  if (!marker_ || !T_world_tracker_) return std::nullopt;
  marker_->wait_idle();
  (void)marker_->take();  // an earlier frame's: its pose in the tracker's world is lost
  marker_->offer(frame.colour, Pose::identity());
  marker_->wait_idle();
  const auto sighting = marker_->take();
  marker_in_view_ = sighting && sighting->found;
  if (!marker_in_view_) return std::nullopt;
  return T_world_tracker_->inverse() * sighting->T_world_camera;
}

void WorldAnchor::wait_for_detection() {
  if (marker_) marker_->wait_idle();
}

void WorldAnchor::blend(const Pose& measured) {
  if (!T_world_tracker_) {
    T_world_tracker_ = measured;  // nothing drawn yet: nothing to jump from
    return;
  }
  const double step = world_step_m(*T_world_tracker_, measured);
  const double limit = config_.max_step_mm * 1e-3;
  const double s = step * kBlend > limit ? limit / step : kBlend;
  // Blend the inverse: the world origin in the tracker's world moves in a straight line.
  T_world_tracker_ = interpolate(T_world_tracker_->inverse(), measured.inverse(), s).inverse();
}

std::optional<Pose> WorldAnchor::update(const RgbdFrame& frame,
                                        const std::optional<Pose>& T_tracker_camera) {
  if (!T_tracker_camera) return T_world_tracker_;  // nothing relates this frame to the world
  // `rig` and `floor` are fixed at start-up; a marker is followed whenever it is seen.
  if (T_world_tracker_ && config_.anchor != "marker") return T_world_tracker_;
  if (const auto measured = measure(frame, *T_tracker_camera)) blend(*measured);
  return T_world_tracker_;
}

}  // namespace probeless::world
