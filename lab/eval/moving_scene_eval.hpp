#pragma once
// `probeless eval render --source sim --scene NAME` (issue #21 item 6; docs/fusion.md): the sim
// as judge of nearby real geometry in a virtual object's reflection. The service's light stage
// runs on a moving-object scene (drivers/sim/sim_moving_scene.hpp); at every light snapshot a
// chrome sphere at the light point is rendered under the captured environment and under the
// truth (the sim's room and the scene's object seen from the sphere's centre at that moment),
// and the report gives the error over the directions that see the object and how long the
// reflection takes to follow an arrival or a removal.
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "app/pipeline/service_config.hpp"
#include "app/render/environment.hpp"
#include "drivers/sim/sim_moving_scene.hpp"

namespace probeless::eval {

// Where the environment a virtual object is lit by comes from: the seam issue #21's surfel
// fusion (items 1-5: the surfel model and the per-object environment map, thesis 6.2.2-6.2.7)
// plugs into. The judge runs each scene once per source and reports them side by side.
enum class EnvironmentSource {
  // Today's: the nearest keyframe reprojected through the room box ([light] room) with one
  // colour frame projected below the light point's horizon ([light] colour_fill,
  // kernels/light/colour_fill.hpp).
  ColourFillRoomBox,
  // The keyframe (today's snapshot, the colour fill included), then the surfels of a surfel map
  // fused from every RGB-D frame (truth poses) rendered over it from the object's position with
  // the dilate/erode gap fill (thesis 6.2.2, 6.2.7): the CPU references of
  // kernels/fusion/surfel_{map,environment}_reference.hpp, run by the judge. Not in the service.
  SurfelFusion,
};
const char* to_string(EnvironmentSource source);
// The surfel map behind SurfelFusion (both with truth poses, the environment on the CPU).
enum class FusionMap { Reference, Device };
const char* to_string(FusionMap map);  // "reference", "device"
bool implemented(EnvironmentSource source);

struct MovingSceneEvalOptions {
  sim::MovingScene scene = sim::MovingScene::BoxAppears;
  std::string sim_spec;  // extra sim options, after the scene's own (trajectory=orbit, seed=2)
  ServiceConfig config;  // objects, [light]; its source must be the sim
  int truth_supersample = 2;
  int sphere_image_size = 256;
  // Which surfel map the SurfelFusion column runs: the CPU reference, or the OpenCL map
  // (kernels/fusion/surfel_map.hpp) on a context of its own (docs/fusion.md "The device map in
  // the judge").
  FusionMap fusion_map = FusionMap::Reference;
  // Non-empty: DIR/<scene>_<source>_<arrival|removal>.png, the sphere (captured | truth |
  // difference x4) at the first snapshot 0.5 s or more after each event.
  std::string dump_dir;
};

// One event's response: presence is how much of the true change over the event's directions
// the captured reflection has made since the last snapshot before the change (0 none, 1 all).
struct PresenceSample {
  double t_s = 0;
  double presence = 0;
};

struct EventResult {
  sim::SceneEvent event;
  int mask_pixels = 0;  // sphere pixels that see the object before or after the change
  // Where the captured reflection stood before the change on the same scale (0: the truth
  // before, 1: the truth after): a removal's near 1 says the object was hardly ever shown, so
  // the reflection had little of it to lose (presence is then small however fast it went).
  double before_position = 0;
  std::vector<PresenceSample> samples;
  std::optional<double> response_s;  // empty: the reflection had not followed by the end
};

// One judged snapshot: the sphere's error over the pixels that see the object then, and
// their mean luminance under the captured light and the truth (what the error is made of).
struct SnapshotSample {
  double t_s = 0;
  int near_object_pixels = 0;
  double near_object_rel_rmse = 0;
  double captured_luminance = 0, truth_luminance = 0;
};

struct SceneMetrics {
  EnvironmentSource source = EnvironmentSource::ColourFillRoomBox;
  // Relative RMSE of the chrome sphere over the pixels that see the object, pooled over the
  // judged snapshots (sqrt(sum |c - t|^2 / sum |t|^2) over RGB).
  double near_object_rel_rmse = 0;
  long near_object_pixels = 0;       // summed over the snapshots
  double whole_sphere_rel_rmse = 0;  // the same over the whole sphere: ghosts show here
  std::vector<SnapshotSample> samples;
  std::vector<EventResult> events;
  std::optional<double> arrival_s, removal_s;  // the events' responses, by kind
  int snapshots = 0;                           // judged (from kJudgeFromS on)
  int fisheye_frames = 0;
};

struct MovingSceneReport {
  std::string scene;
  SceneMetrics with_fusion;     // EnvironmentSource::SurfelFusion, or today's in its place
  SceneMetrics without_fusion;  // EnvironmentSource::ColourFillRoomBox
  bool fusion_implemented = false;
  FusionMap fusion_map = FusionMap::Reference;
  double judged_from_s = 0;
};

// Snapshots before this world time are the light stage's start-up, not the scene: not judged.
inline constexpr double kJudgeFromS = 1.0;
// A sphere pixel sees the object when at least this share of its truth texel's rays meet it.
inline constexpr double kObjectShare = 0.5;
// The reflection has followed a change once its presence stays at or above this.
inline constexpr double kPresenceThreshold = 0.5;

// Throws std::invalid_argument for options it cannot run (MovingScene::None, not the sim, no
// objects) and std::runtime_error when a stage fails.
MovingSceneReport evaluate_moving_scene(const MovingSceneEvalOptions& options);

// The pieces, unit-tested. Presence: sum (c - c0) . (after - before) / sum |after - before|^2
// over RGB of the mask; 0 when the truth did not change there.
double change_presence(const render::ImageRGBAF& captured,
                       const render::ImageRGBAF& captured_before,
                       const render::ImageRGBAF& truth_before,
                       const render::ImageRGBAF& truth_after, const std::vector<bool>& mask);
// The time from event_t_s to the first sample (at or after before_t_s) from which on every
// sample's presence is >= threshold, 0 when that sample is before the event; empty when the
// last sample is below it or there is none.
std::optional<double> settle_time(std::span<const PresenceSample> samples, double before_t_s,
                                  double event_t_s, double threshold);
// The pixels of a sphere render lit by an object-share environment (truth_environment's
// object_share) whose share is >= min_share; alpha marks the sphere.
std::vector<bool> share_mask(const render::ImageRGBAF& share_render, double min_share);

}  // namespace probeless::eval
