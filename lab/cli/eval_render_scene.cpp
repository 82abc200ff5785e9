// probeless eval render --scene NAME | --list-scenes: the sim as judge of nearby real geometry
// in a virtual object's reflection (issue #21 item 6; docs/fusion.md).
#include "lab/cli/eval_render_scene.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "drivers/sim/sim_moving_scene.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {

nlohmann::json seconds_or_null(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json();
}

const char* kind_name(sim::SceneEvent::Kind k) {
  return k == sim::SceneEvent::Kind::Arrival ? "arrival" : "removal";
}

// "measured", or why the time is null: the scene has no such event, or the reflection had not
// followed it by the end of the run.
std::string status(const eval::SceneMetrics& m, sim::SceneEvent::Kind kind) {
  for (const auto& e : m.events)
    if (e.event.kind == kind) return e.response_s ? "measured" : "not within the run";
  return "no such event in this scene";
}

nlohmann::json samples_json(const eval::SceneMetrics& m) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& s : m.samples)
    out.push_back({{"t_s", s.t_s},
                   {"near_object_pixels", s.near_object_pixels},
                   {"near_object_rel_rmse", s.near_object_rel_rmse},
                   {"captured_luminance", s.captured_luminance},
                   {"truth_luminance", s.truth_luminance}});
  return out;
}

nlohmann::json events_json(const eval::SceneMetrics& m) {
  nlohmann::json events = nlohmann::json::array();
  for (const auto& e : m.events) {
    nlohmann::json samples = nlohmann::json::array();
    for (const auto& s : e.samples) samples.push_back({{"t_s", s.t_s}, {"presence", s.presence}});
    events.push_back({{"kind", kind_name(e.event.kind)},
                      {"t_s", e.event.t_s},
                      {"before_t_s", e.event.before_t_s},
                      {"mask_pixels", e.mask_pixels},
                      {"before_position", e.before_position},
                      {"response_s", seconds_or_null(e.response_s)},
                      {"samples", samples}});
  }
  return events;
}

std::string optional_s(const std::optional<double>& v, const std::string& why) {
  return v ? fmt::format("{:.3f} s", *v) : why;
}

void print(const eval::SceneMetrics& m, const std::string& label) {
  std::cout << fmt::format(
      "  {}: near-object relative RMSE {:.4f} ({} px over {} snapshots), whole sphere {:.4f}; "
      "arrival {}, removal {}\n",
      label, m.near_object_rel_rmse, m.near_object_pixels, m.snapshots, m.whole_sphere_rel_rmse,
      optional_s(m.arrival_s, status(m, sim::SceneEvent::Kind::Arrival)),
      optional_s(m.removal_s, status(m, sim::SceneEvent::Kind::Removal)));
  for (const auto& s : m.samples)
    if (s.near_object_pixels > 0)
      std::cout << fmt::format(
          "    t {:5.2f} s  {:5d} px  error {:7.4f}  luminance captured {:9.3f}  truth {:9.3f}\n",
          s.t_s, s.near_object_pixels, s.near_object_rel_rmse, s.captured_luminance,
          s.truth_luminance);
  for (const auto& e : m.events) {
    std::cout << fmt::format(
        "    {} at {:.2f} s ({} px, stood at {:+.2f} before); presence:", kind_name(e.event.kind),
        e.event.t_s, e.mask_pixels, e.before_position);
    for (const auto& s : e.samples) std::cout << fmt::format(" {:.2f}:{:+.2f}", s.t_s, s.presence);
    std::cout << "\n";
  }
}

}  // namespace

void list_moving_scenes() {
  for (const auto& s : sim::moving_scenes()) std::cout << s.name << "\n";
}

void run_eval_render_scene(const SceneCommandOptions& c) {
  const auto scene = sim::find_moving_scene(c.scene);
  if (!scene)
    throw CommandError(fmt::format("eval render: unknown scene '{}' (scenes: {})", c.scene,
                                   sim::moving_scene_names(", ")));
  eval::MovingSceneEvalOptions o;
  o.scene = *scene;
  o.sim_spec = c.sim_spec;
  o.config = c.config;
  if (c.fusion_map == "device")
    o.fusion_map = eval::FusionMap::Device;
  else if (c.fusion_map != "reference")
    throw CommandError(
        fmt::format("eval render: unknown --fusion-map '{}' (reference, device)", c.fusion_map));
  o.dump_dir = c.dump_dir;
  if (!o.dump_dir.empty()) std::filesystem::create_directories(o.dump_dir);
  eval::MovingSceneReport r;
  try {
    r = eval::evaluate_moving_scene(o);
  } catch (const std::invalid_argument& e) {
    throw CommandError(e.what());
  }
  std::cout << fmt::format(
      "eval render --scene {}: {} fisheye frames; chrome sphere judged from t = {:.1f} s\n",
      r.scene, r.without_fusion.fisheye_frames, r.judged_from_s);
  print(r.without_fusion, fmt::format("without fusion ({})", to_string(r.without_fusion.source)));
  if (r.fusion_implemented)
    print(r.with_fusion, fmt::format("with fusion ({}: the {} surfel map and per-object "
                                     "environment, truth poses; not the service's path)",
                                     to_string(r.with_fusion.source),
                                     r.fusion_map == eval::FusionMap::Device ? "OpenCL" : "CPU"));
  else
    std::cout << "  with fusion: not implemented (issue #21 items 1-5); the *_without_fusion "
                 "columns are today's method and so are the fusion columns\n";
  if (c.json.empty()) return;
  const auto& f = r.with_fusion;
  const auto& n = r.without_fusion;
  const nlohmann::json j{
      {"scene", r.scene},
      // "implemented" in the judge by the CPU references (truth poses), not in the service.
      {"fusion", !r.fusion_implemented ? "not implemented"
                 : r.fusion_map == eval::FusionMap::Device
                     ? "implemented (opencl map and environment, truth poses)"
                     : "implemented (cpu reference, truth poses)"},
      {"fusion_map", to_string(r.fusion_map)},
      {"environment_source", to_string(f.source)},
      {"environment_source_without_fusion", to_string(n.source)},
      {"near_object_rel_rmse", f.near_object_rel_rmse},
      {"arrival_s", seconds_or_null(f.arrival_s)},
      {"removal_s", seconds_or_null(f.removal_s)},
      {"arrival_status", status(f, sim::SceneEvent::Kind::Arrival)},
      {"removal_status", status(f, sim::SceneEvent::Kind::Removal)},
      {"whole_sphere_rel_rmse", f.whole_sphere_rel_rmse},
      {"near_object_rel_rmse_without_fusion", n.near_object_rel_rmse},
      {"arrival_s_without_fusion", seconds_or_null(n.arrival_s)},
      {"removal_s_without_fusion", seconds_or_null(n.removal_s)},
      {"arrival_status_without_fusion", status(n, sim::SceneEvent::Kind::Arrival)},
      {"removal_status_without_fusion", status(n, sim::SceneEvent::Kind::Removal)},
      {"whole_sphere_rel_rmse_without_fusion", n.whole_sphere_rel_rmse},
      {"near_object_pixels", n.near_object_pixels},
      {"snapshots", n.snapshots},
      {"fisheye_frames", n.fisheye_frames},
      {"judged_from_s", r.judged_from_s},
      {"object_share_threshold", eval::kObjectShare},
      {"presence_threshold", eval::kPresenceThreshold},
      {"events", events_json(f)},
      {"events_without_fusion", events_json(n)},
      {"snapshot_samples", samples_json(f)},
      {"snapshot_samples_without_fusion", samples_json(n)}};
  write_json_report(c.json, j);
}

}  // namespace probeless::cli
