#pragma once
// The set of environment-map keyframes (thesis ch. 6; docs/light-capture.md): each a cubemap
// of radiance and texel state on the device plus the world position it was captured from.
// A capture farther than new_keyframe_distance_m from every keyframe starts a new one there,
// seeded from the nearest with every texel unobserved (alpha 0), so that new observations
// replace what it inherited; old keyframes are kept and updated again when the rig returns,
// up to max_keyframes: past that, the one farthest from the rig is dropped (docs/light-capture.md
// "How many keyframes").
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "kernels/envmap/envmap_types.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::envmap {

struct KeyframeConfig {
  int face_size = 128;  // texels per face edge (ARCore serves 16; the issue asks >= 128)
  // A new keyframe beyond this distance from the nearest (metres). The thesis leaves the
  // value to the application; 0.5 m keeps the parallax of a wall 2 m away under ~15 deg.
  double new_keyframe_distance_m = 0.5;
  // Keyframes kept at most. The thesis keeps every one; a rig that wanders (or a tracker that
  // drifts) then grows the set without bound: ~15 MB resident each at 192 px faces in the
  // service, 265 keyframes and 4.3 GB after an hour's soak (issue #20). The service sets it
  // from [light] max_keyframes (app/pipeline/service_config.hpp).
  int max_keyframes = 16;
};

struct Keyframe {
  // Stable for the keyframe's life and never reused: what per-keyframe caches are keyed by
  // (not its index in keyframes(), which shifts when another is dropped).
  int id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world, where it was captured from
  DeviceImage<float, 4> texels;                        // n x 6n, envmap_types.hpp
  DeviceImage<float, 4> pending;   // the best-score rule's samples of the current cycle
  std::uint64_t updates = 0;       // frames that updated it
  std::uint64_t last_capture = 0;  // the set's capture count when a capture last chose it
};

class KeyframeSet {
 public:
  KeyframeSet(ComputeContext& ctx, const KeyframeConfig& config = {});
  const KeyframeConfig& config() const { return config_; }

  // The keyframe a capture from `position` updates: the nearest, unless it is farther than the
  // threshold (or there is none): then a new one at `position`, seeded from the nearest (the
  // first is all zeros, unobserved). A new one beyond max_keyframes drops the keyframe
  // farthest from `position` (of equally far ones, the one a capture chose least recently)
  // with its device memory. Switching keyframe clears the old one's pending samples.
  Keyframe& for_capture(const Eigen::Vector3d& position);
  // The keyframe nearest to `position` (to light an object there); null when there is none.
  const Keyframe* nearest(const Eigen::Vector3d& position) const;
  // The keyframe with this id; null when there is none (never was, or dropped).
  const Keyframe* find(int id) const;
  Keyframe* find(int id);
  // In the order they were made; indices shift when one is dropped (use Keyframe::id).
  const std::vector<std::unique_ptr<Keyframe>>& keyframes() const { return keyframes_; }
  int active_id() const { return active_; }           // -1: none (yet, or it was dropped)
  std::uint64_t dropped() const { return dropped_; }  // keyframes dropped for max_keyframes

 private:
  Keyframe* nearest_mutable(const Eigen::Vector3d& position) const;
  void drop_farthest_from(const Eigen::Vector3d& position, const Keyframe& kept);

  ComputeContext& ctx_;
  KeyframeConfig config_;
  ::cl::Kernel seed_;
  std::vector<std::unique_ptr<Keyframe>> keyframes_;
  int active_ = -1;
  int next_id_ = 0;
  std::uint64_t captures_ = 0, dropped_ = 0;
};

}  // namespace probeless::envmap
