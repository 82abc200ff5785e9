// probeless eval occlusion: every occlusion method against ground truth on one dataset
// (docs/occlusion.md "Evaluation"). Tables go to stdout, --json and --plots to files.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "lab/cli/lab_commands.hpp"
#include "lab/eval/occlusion_eval.hpp"

namespace probeless::cli {
namespace {

struct Options {
  std::string dataset;
  std::string json;
  std::string plots;
  std::string methods;
  std::string crop;
  int frames = 8;
  std::uint64_t seed = 1;
  int max_scenes = 0;
  int wide_subsample = 0;  // 0 = the method's default
  int hole_core_px = -1;   // -1 = the shipped default
  double beyond_range_m = BeyondRangeRule{}.far_mm / 1000.0;
  bool stabilised = false;
  std::string stabiliser;  // W:COLOUR:DEPTH_MM:DEPTH_REL
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

void run(const Options& o) {
  eval::EvalOptions opts;
  if (!o.methods.empty()) opts.methods = split(o.methods);
  if (o.frames < 1) throw CommandError("--frames must be at least 1");
  opts.frames = o.frames;
  opts.seed = o.seed;
  opts.max_scenes = o.max_scenes;
  opts.plots_dir = o.plots;
  opts.stabilised = o.stabilised;
  if (!o.stabiliser.empty()) {
    char c1 = 0, c2 = 0, c3 = 0;
    auto& p = opts.stabiliser;
    std::istringstream in(o.stabiliser);
    if (!(in >> p.history_weight >> c1 >> p.colour_range >> c2 >> p.depth_tolerance_mm >> c3 >>
          p.depth_tolerance_rel) ||
        c1 != ':' || c2 != ':' || c3 != ':')
      throw CommandError("--stabiliser: expected WEIGHT:COLOUR_RANGE:DEPTH_MM:DEPTH_REL");
  }
  if (!o.crop.empty()) {
    char x = 0;
    std::istringstream in(o.crop);
    if (!(in >> opts.crop_width >> x >> opts.crop_height) || x != 'x' || opts.crop_width <= 0 ||
        opts.crop_height <= 0)
      throw CommandError("--crop: expected WxH, e.g. 96x64");
  }
  if (o.wide_subsample > 0) opts.settings.cvf.cvf.wide.subsample = o.wide_subsample;
  std::string protocol;
  auto cases = eval::load_cases(o.dataset, opts, &protocol);
  // The trimap is exact and no sensor's (docs/occlusion.md).
  if (protocol == "alphamatting") occlusion::use_exact_trimap(opts.settings);
  if (o.hole_core_px >= 0) opts.settings.cvf.hole_core_px = o.hole_core_px;
  opts.beyond_range.far_mm = static_cast<std::uint16_t>(std::lround(o.beyond_range_m * 1000.0));
  ComputeContext ctx;
  spdlog::info("eval occlusion: {} cases on {}", cases.size(), ctx.describe());
  auto report = eval::evaluate(ctx, cases, opts);
  report.protocol = protocol;
  std::cout << format_report(report) << std::flush;
  if (!o.json.empty()) {
    write_json_report(o.json, eval::report_json(report));
  }
}

}  // namespace

void add_eval_occlusion_command(CLI::App& eval) {
  auto o = std::make_shared<Options>();
  auto* cmd = eval.add_subcommand(
      "occlusion", "Occlusion mattes of every method against ground truth (MSE, temporal noise)");
  cmd->add_option(
         "--dataset", o->dataset,
         "middlebury:DIR, alphamatting:DIR, frames:DIR or sim[:OPTIONS] (docs/occlusion.md)")
      ->required();
  cmd->add_option("--json", o->json, "Write the scores as JSON to this file");
  cmd->add_option("--plots", o->plots,
                  "Write bar plots (SVG) and example mattes (PNG) into this directory");
  cmd->add_option(
      "--methods", o->methods,
      "Comma-separated subset of: cvf,cvf_thesis,direct1,direct2,guided,bilateral,crabb,"
      "arcore_soft,meta_soft");
  cmd->add_option("--frames", o->frames, "Noisy frames K per Middlebury scene")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "First noise seed")->capture_default_str();
  cmd->add_option("--crop", o->crop, "Evaluate the centre WxH crop of every frame");
  cmd->add_option("--max-scenes", o->max_scenes, "Evaluate at most this many scenes (0 = all)");
  cmd->add_option("--cvf-subsample", o->wide_subsample,
                  "The shipped CVF's wide filter subsampling (1 = exact, its default; 2 = fast "
                  "guided filter)");
  cmd->add_option("--cvf-hole-core", o->hole_core_px,
                  "The shipped CVF's hole-core radius, px (0 = holes are only 'process'; default: "
                  "the shipped value; docs/occlusion.md \"Occluders the sensor cannot see\")")
      ->check(CLI::Range(0, 64));
  cmd->add_option("--beyond-range-m", o->beyond_range_m,
                  "Holes whose nearest depth is this far are beyond the sensor's range and filled "
                  "far before every method, as the service does (0 = off; docs/occlusion.md "
                  "\"Beyond the sensor's range\")")
      ->check(CLI::Range(0.0, 20.0))
      ->capture_default_str();
  cmd->add_flag("--stabilised", o->stabilised,
                "Also score every method with temporal stabilisation (columns METHOD+stab)");
  cmd->add_option("--stabiliser", o->stabiliser,
                  "The stabiliser's parameters WEIGHT:COLOUR_RANGE:DEPTH_MM:DEPTH_REL (default "
                  "0.6:0.1:15:0.02; docs/occlusion.md)");
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli
