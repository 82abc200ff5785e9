// probeless eval hdr: a simulated linear camera brackets a real HDR image with the bracket
// sequencer; the merged cycle is compared with the image (docs/bracketing.md).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "drivers/bracket/bracket_simulation.hpp"
#include "drivers/io/hdr_image.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {

struct Options {
  std::string image;
  std::vector<int> bits{8, 12};
  std::string json;
  HdrEvalOptions eval;
};

nlohmann::json to_json(const HdrEvalReport& r) {
  return {{"image", r.image},
          {"bits", r.bits},
          {"merge_cycles", r.merge_cycles},
          {"weights", r.weights == MergeWeights::Hat ? "hat" : "noise"},
          {"median_rel_error", r.median_rel_error},
          {"p95_rel_error", r.p95_rel_error},
          {"measurable_fraction", r.measurable_fraction},
          {"settle_cycles", r.settle_cycles},
          {"settled", r.settled},
          {"stops", {{"low", r.low_stop}, {"medium", r.medium_stop}, {"high", r.high_stop}}},
          {"exposure_values",
           {{"low", r.low_exposure}, {"medium", r.medium_exposure}, {"high", r.high_exposure}}},
          {"scene_range", r.scene_range}};
}

void run(const Options& o) {
  ImageRGBF image;
  try {
    image = read_hdr_image(o.image);
  } catch (const std::exception& e) {
    throw CommandError(e.what());
  }
  std::vector<HdrEvalReport> reports;
  for (int bits : o.bits) {
    HdrEvalOptions opts = o.eval;
    opts.bits = bits;
    HdrEvalReport r;
    try {
      r = evaluate_bracketing(image, opts);
    } catch (const std::invalid_argument& e) {
      throw CommandError(e.what());
    }
    r.image = o.image;
    std::cout << fmt::format(
        "{} {}-bit: median rel error {:.4f}, p95 {:.4f}, measurable {:.4f}, settled after {} "
        "cycles{}, stops L {} M {} H {} (scene range {:.3g}:1; merged {} cycles, {} weights)\n",
        o.image, bits, r.median_rel_error, r.p95_rel_error, r.measurable_fraction, r.settle_cycles,
        r.settled ? "" : " (NOT settled)", r.low_stop, r.medium_stop, r.high_stop, r.scene_range,
        r.merge_cycles, r.weights == MergeWeights::Hat ? "hat" : "noise");
    reports.push_back(r);
  }
  if (!o.json.empty()) {
    nlohmann::json j;
    if (reports.size() == 1) {
      j = to_json(reports[0]);
    } else {
      j = nlohmann::json::array();
      for (const auto& r : reports) j.push_back(to_json(r));
    }
    write_json_report(o.json, j);
  }
}

}  // namespace

void add_eval_hdr_command(CLI::App& eval) {
  auto o = std::make_shared<Options>();
  auto* cmd = eval.add_subcommand(
      "hdr", "Bracket a real HDR image with a simulated 8/12-bit camera; merged radiance error");
  cmd->add_option("--image", o->image, "Radiance .hdr or OpenEXR .exr image")->required();
  cmd->add_option("--bits", o->bits, "Camera bit depth(s): 8, 12 (default both)")
      ->check(CLI::IsMember({8, 12}));
  cmd->add_option("--json", o->json,
                  "Write the report as JSON (an object for one bit depth, else an array)");
  cmd->add_option("--cycles", o->eval.cycles, "L-M-H-M cycles simulated")->capture_default_str();
  cmd->add_option("--merge-cycles", o->eval.merge_cycles, "Merge the last N cycles")
      ->capture_default_str();
  cmd->add_option("--seed", o->eval.seed, "Noise seed")->capture_default_str();
  cmd->add_option("--full-well", o->eval.full_well_e, "Electrons at full scale (0: 10000)");
  cmd->add_option("--read-noise", o->eval.read_noise_dn, "Read noise in DN (< 0: the default)");
  cmd->add_flag(
      "!--fixed-medium", o->eval.sequencer.adapt_medium,
      "Keep the medium exposure at the start value (the camera's AE) instead of adapting it");
  cmd->add_option("--weights", o->eval.weights,
                  "Merge weights: noise (inverse variance under the camera model) or hat")
      ->transform(CLI::CheckedTransformer(std::map<std::string, MergeWeights>{
          {"noise", MergeWeights::NoiseOptimal}, {"hat", MergeWeights::Hat}}))
      ->capture_default_str();
  cmd->add_option("--mains-hz", o->eval.sequencer.mains_hz, "Mains frequency (50 or 60)")
      ->capture_default_str();
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli
