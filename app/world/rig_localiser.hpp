#pragma once
// Where the rig is in the world, per RGB-D frame (docs/tracking.md "Poses in the service"):
// the colour camera's pose from `[tracking] method` (the dense tracker, the source's truth,
// or a static rig) composed with the world anchor,
//   T_world_rig = T_world_tracker * T_tracker_camera * T_rgb_rig.
// Unknown (nullopt) while tracking is lost or the world is not found yet: the service then
// draws no virtual object rather than one at a wrong pose. Runs on the processing thread.
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "app/world/world_anchor.hpp"
#include "app/world/world_config.hpp"
#include "core/calibration.hpp"
#include "core/frame.hpp"
#include "kernels/tracking/dense_tracker.hpp"

namespace probeless {
class ComputeContext;
}

namespace probeless::world {

// What /status "tracking" says (docs/tracking.md "Status and failure").
struct LocaliserStatus {
  tracking::TrackingState state = tracking::TrackingState::Off;
  std::string method, anchor;
  bool anchor_found = false;
  std::optional<Pose> T_world_rig;  // of the last frame, when known
  int keyframes = 0;
  std::uint64_t lost_count = 0;  // times tracking went from known to lost
  nlohmann::json to_json() const;
};

class RigLocaliser {
 public:
  // `ctx`: the processing thread's OpenCL context for the dense tracker (null: its CPU
  // reference). Throws std::invalid_argument for an unknown method or anchor.
  RigLocaliser(const TrackingConfig& tracking, const WorldConfig& world,
               const RigCalibration& calibration, ComputeContext* ctx);
  ~RigLocaliser();
  RigLocaliser(const RigLocaliser&) = delete;
  RigLocaliser& operator=(const RigLocaliser&) = delete;

  std::optional<Pose> locate(const RgbdFrame& frame);
  const LocaliserStatus& status() const { return status_; }

 private:
  std::optional<Pose> camera_in_tracker(const RgbdFrame& frame);

  TrackingConfig config_;
  RigCalibration calibration_;
  std::unique_ptr<tracking::DenseTracker> tracker_;
  WorldAnchor anchor_;
  LocaliserStatus status_;
};

}  // namespace probeless::world
