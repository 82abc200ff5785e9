#pragma once
// Where the world is (`[world] anchor`, docs/tracking.md "World anchoring"): the tracker's
// world (its first camera) in the anchored world, T_world_tracker. `rig`: the rig's world as
// the source gives it at the first frame; `floor`: the dominant horizontal plane of the first
// depth image that has one (floor_plane.hpp); `marker`: the board or marker, whenever it is
// seen while tracking runs, its sightings blended into the estimate at a bounded rate so that
// the objects glide onto a new sighting instead of jumping (no step over max_step_mm).
#include <memory>
#include <optional>
#include <string>

#include "app/world/floor_plane.hpp"
#include "app/world/world_config.hpp"
#include "core/calibration.hpp"
#include "core/frame.hpp"

namespace probeless::world {

class MarkerWorker;

class WorldAnchor {
 public:
  // Throws std::invalid_argument for an unknown anchor or a marker spec the detector refuses.
  WorldAnchor(const WorldConfig& config, const RigCalibration& calibration);
  ~WorldAnchor();
  WorldAnchor(const WorldAnchor&) = delete;
  WorldAnchor& operator=(const WorldAnchor&) = delete;

  // One frame, with the colour camera's pose in the tracker's world when it is known.
  // Returns T_world_tracker once the world has been found, else nullopt.
  std::optional<Pose> update(const RgbdFrame& frame, const std::optional<Pose>& T_tracker_camera);

  const std::string& kind() const { return config_.anchor; }
  bool found() const { return T_world_tracker_.has_value(); }
  // The marker was seen in the last detection that finished (marker anchoring only).
  bool marker_in_view() const { return marker_in_view_; }
  // Marker anchoring, once the world is known: the colour camera of `frame` in the tracker's
  // world from a sighting of the marker in this very frame (detected now, waiting for the
  // detector: the tracker is lost and nothing is drawn meanwhile); nullopt when the marker is
  // not in view or the anchor is not a marker.
  std::optional<Pose> relocalise(const RgbdFrame& frame);
  // Marker anchoring detects on its own thread (marker_worker.hpp); a test that wants each
  // frame's sighting applied to that frame waits for it here.
  void wait_for_detection();

 private:
  std::optional<Pose> measure(const RgbdFrame& frame, const Pose& T_tracker_camera);
  void blend(const Pose& measured);

  WorldConfig config_;
  RigCalibration calibration_;
  FloorParams floor_;
  std::unique_ptr<MarkerWorker> marker_;
  std::optional<Pose> T_world_tracker_;
  bool marker_in_view_ = false;
};

// How far a change of T_world_tracker moves the objects: the world origin's displacement in
// the tracker's (real) world plus the rotation's arc at `reach_m` from it, metres.
double world_step_m(const Pose& T_world_tracker_a, const Pose& T_world_tracker_b,
                    double reach_m = 0.25);

}  // namespace probeless::world
