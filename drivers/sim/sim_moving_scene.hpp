#pragma once
// The moving-object scenes (issue #21 item 6; docs/fusion.md "The judge"): a real object moves
// next to the point where `eval render` stands its virtual chrome sphere
// (light_probe_position()), at known world times, so that how fast and how well a method puts
// nearby real geometry into the sphere's reflection can be measured against the truth
// (thesis 6.2.7: the environment map rendered from the object's own position). Opened with
// `sim:scene=NAME`; each scene's objects take the arm's place in both cameras. Everything is a
// function of world time alone: deterministic for any seed, pacing or thread count.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/sim/sim_rig.hpp"
#include "drivers/sim/sim_world.hpp"

namespace probeless::sim {

// A change of the scene. The object moves (or appears, or vanishes) between before_t_s and t_s
// and is at rest from t_s on: arrival and removal times are measured from t_s.
struct SceneEvent {
  enum class Kind { Arrival, Removal };
  Kind kind;
  double t_s;         // world time the scene reaches its new state
  double before_t_s;  // a world time that shows the state before the change
};

struct MovingSceneSpec {
  MovingScene id;
  std::string_view name;
  std::string_view summary;  // one line, for --list-scenes' readers and the docs
  // The judge runs world time [0, duration_s): lamp B stays on throughout (it switches off
  // at 6 s, SimWorld::lamp_state), so the only change is the scene's object.
  double duration_s;
  std::span<const SceneEvent> events;
};

// Every scene except None, in the order `eval render --list-scenes` prints them.
std::span<const MovingSceneSpec> moving_scenes();
// Throws std::invalid_argument for MovingScene::None.
const MovingSceneSpec& moving_scene_spec(MovingScene scene);
std::optional<MovingScene> find_moving_scene(std::string_view name);
// The scene names joined by `separator`: what an error about a bad name lists.
std::string moving_scene_names(std::string_view separator);

// The scene's real objects at world time t, in the world frame (empty for None, and for a
// removed or not yet appeared box).
Occluder moving_scene_objects(MovingScene scene, double t);

}  // namespace probeless::sim
