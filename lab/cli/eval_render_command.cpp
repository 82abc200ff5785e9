// probeless eval render --source sim: the virtual objects lit by the service's captured light
// against the same objects under the sim's ground-truth light (issue #6; docs/rendering.md
// "eval render"); with --scene, the moving-object judge (docs/fusion.md).
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "lab/cli/eval_render_scene.hpp"
#include "lab/cli/lab_commands.hpp"
#include "lab/eval/render_eval.hpp"

namespace probeless::cli {
namespace {

struct Options {
  std::string source = "sim";
  std::string config_path;
  std::string json;
  eval::RenderEvalOptions eval;
  std::string scene;  // a moving-object scene (docs/fusion.md); empty: the default protocol
  std::string fusion_map = "reference";  // with --scene: which surfel map the fusion runs
  bool list_scenes = false;
  bool orbit_given = false;       // --orbit or --after: the default protocol's only
  bool fusion_map_given = false;  // --fusion-map: a --scene's only
};

std::string optional_s(const std::optional<double>& v) {
  return v ? fmt::format("{:.2f} s", *v) : std::string("not within the run");
}

void run(Options& o) {
  if (o.list_scenes) {
    list_moving_scenes();
    return;
  }
  if (o.source != "sim") throw CommandError("eval render: only --source sim has ground truth");
  o.eval.config = o.config_path.empty() ? ServiceConfig{} : load_service_config(o.config_path);
  o.eval.config.source = "sim";
  if (!o.scene.empty()) {
    if (o.orbit_given)
      throw CommandError("eval render: --orbit and --after do not apply to a --scene");
    run_eval_render_scene(
        {o.scene, o.eval.sim_spec, o.json, o.eval.dump_dir, o.eval.config, o.fusion_map});
    return;
  }
  if (o.fusion_map_given)
    throw CommandError(
        "eval render: --fusion-map applies to a --scene only (the default "
        "protocol runs no fusion)");
  if (!o.eval.dump_dir.empty()) std::filesystem::create_directories(o.eval.dump_dir);
  eval::RenderEvalReport r;
  try {
    r = eval::evaluate_render_sim(o.eval);
  } catch (const std::invalid_argument& e) {
    throw CommandError(e.what());
  }
  std::cout << fmt::format(
      "eval render: {} fisheye frames, {} light snapshots; compared at t = {:.2f} s after {:.1f} s "
      "of orbit\n",
      r.fisheye_frames, r.snapshots, r.compare_t_s, o.eval.orbit_s);
  std::cout << fmt::format("  objects ({} px): relative error {:.4f}\n", r.object_pixels,
                           r.object_rel_error);
  std::cout << fmt::format(
      "  ground shadow ({} px): relative error {:.4f}; mean change captured {:.4f}, truth {:.4f}\n",
      r.shadow_pixels, r.shadow_rel_error, r.shadow_mean_captured, r.shadow_mean_truth);
  std::cout << fmt::format(
      "  chrome sphere ({} px): relative RMSE {:.4f} (upper half {:.4f}, lower {:.4f}){}\n",
      r.sphere_pixels, r.sphere_rel_rmse, r.sphere_rel_rmse_upper, r.sphere_rel_rmse_lower,
      o.eval.dump_dir.empty() ? "" : " (" + o.eval.dump_dir + "/chrome_sphere.png)");
  std::cout << fmt::format(
      "  lamp switch at t = {:.1f} s (truth x {:.3f}): objects within 10 % of the truth after "
      "{}; error before {:.3f}, at the end {:.3f}\n",
      r.switch_t_s, r.truth_drop, optional_s(r.lamp_response_s), r.lamp_rel_error_before,
      r.lamp_rel_error_final);
  for (const auto& s : r.lamp)
    std::cout << fmt::format("    t {:6.3f} s  captured {:8.4f}  truth {:8.4f}  error {:.3f}\n",
                             s.t_s, s.captured, s.truth, s.rel_error);
  if (!o.json.empty()) {
    nlohmann::json lamp = nlohmann::json::array();
    for (const auto& s : r.lamp)
      lamp.push_back({{"t_s", s.t_s},
                      {"captured", s.captured},
                      {"truth", s.truth},
                      {"rel_error", s.rel_error}});
    const nlohmann::json j{
        {"object_rel_error", r.object_rel_error},
        {"shadow_rel_error", r.shadow_rel_error},
        {"sphere_rel_rmse", r.sphere_rel_rmse},
        {"sphere_rel_rmse_upper", r.sphere_rel_rmse_upper},
        {"sphere_rel_rmse_lower", r.sphere_rel_rmse_lower},
        {"lamp_response_s",
         r.lamp_response_s ? nlohmann::json(*r.lamp_response_s) : nlohmann::json()},
        {"object_pixels", r.object_pixels},
        {"shadow_pixels", r.shadow_pixels},
        {"shadow_mean_captured", r.shadow_mean_captured},
        {"shadow_mean_truth", r.shadow_mean_truth},
        {"sphere_pixels", r.sphere_pixels},
        {"orbit_s", o.eval.orbit_s},
        {"compare_t_s", r.compare_t_s},
        {"switch_t_s", r.switch_t_s},
        {"truth_drop", r.truth_drop},
        {"lamp_rel_error_before", r.lamp_rel_error_before},
        {"lamp_rel_error_final", r.lamp_rel_error_final},
        {"fisheye_frames", r.fisheye_frames},
        {"snapshots", r.snapshots},
        {"lamp", lamp}};
    write_json_report(o.json, j);
  }
}

}  // namespace

void add_eval_render_command(CLI::App& eval) {
  auto o = std::make_shared<Options>();
  auto* cmd = eval.add_subcommand(
      "render", "Objects lit by the captured light against the sim's ground-truth light");
  cmd->add_option("--source", o->source, "Source with ground truth (sim)")->capture_default_str();
  cmd->add_option("--config", o->config_path,
                  "Service configuration: objects, [ground], [light] (docs/configuration.md)");
  auto* orbit =
      cmd->add_option("--orbit", o->eval.orbit_s, "Seconds of orbit before the comparison")
          ->capture_default_str();
  auto* after = cmd->add_option("--after", o->eval.after_switch_s,
                                "Seconds after the lamp switch the response is followed")
                    ->capture_default_str();
  cmd->add_option("--scene", o->scene,
                  "A moving-object scene (--list-scenes): the sphere's error over the nearby "
                  "object and the arrival and removal times (docs/fusion.md)");
  auto* fusion_map =
      cmd->add_option("--fusion-map", o->fusion_map,
                      "With --scene: the fusion column's surfel map, reference (CPU) or device "
                      "(OpenCL)")
          ->capture_default_str();
  cmd->add_flag("--list-scenes", o->list_scenes, "Print the moving-object scene names and exit");
  cmd->add_option("--sim", o->eval.sim_spec, "Extra sim options (seed=2,fisheye_size=1024,...)");
  cmd->add_option("--json", o->json, "Write the report as JSON");
  cmd->add_option("--dump", o->eval.dump_dir,
                  "Write DIR/chrome_sphere.png (captured | truth | difference x4) and "
                  "DIR/objects.png (captured | truth)");
  cmd->callback([o, orbit, after, fusion_map] {
    o->orbit_given = orbit->count() > 0 || after->count() > 0;
    o->fusion_map_given = fusion_map->count() > 0;
    run(*o);
  });
}

}  // namespace probeless::cli
