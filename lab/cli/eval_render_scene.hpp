#pragma once
// `probeless eval render --scene NAME` and `--list-scenes` (docs/fusion.md).
#include <string>

#include "app/pipeline/service_config.hpp"
#include "lab/eval/moving_scene_eval.hpp"

namespace probeless::cli {

struct SceneCommandOptions {
  std::string scene;     // a name from --list-scenes
  std::string sim_spec;  // extra sim options
  std::string json, dump_dir;
  ServiceConfig config;                  // its source the sim
  std::string fusion_map = "reference";  // "reference" or "device" (eval::FusionMap)
};

// The moving-object scene names, one a line, on stdout.
void list_moving_scenes();
// Throws CommandError for an unknown scene name (listing the valid ones) or options the judge
// cannot run.
void run_eval_render_scene(const SceneCommandOptions& options);

}  // namespace probeless::cli
