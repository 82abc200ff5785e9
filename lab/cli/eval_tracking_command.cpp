// probeless eval tracking: the shipped dense tracker beside OpenCV's odometry on the same
// frames of a TUM RGB-D sequence or the sim, against their ground truth (issue #17 item 5;
// lab/eval/tracking_eval.hpp, docs/tracking.md "Evaluation").
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "kernels/runtime/compute_context.hpp"
#include "lab/cli/lab_commands.hpp"
#include "lab/eval/tracking_eval.hpp"

namespace probeless::cli {
namespace {

struct Options {
  std::string dataset, methods, json, trajectories, per_frame;
  int frames = 0;
};

nlohmann::json number_or_null(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json();
}

std::string cell(const std::optional<double>& v, const char* format) {
  return v ? fmt::format(fmt::runtime(format), *v) : std::string("-");
}

void print(const eval::TrackingEvalReport& r, const eval::TrackingDepthRange& range) {
  std::cout << fmt::format(
      "eval tracking: {}, {} frames; camera {}; depth used {}..{} m; registration anchor at "
      "{:.3f} m on the first optical axis\n",
      r.sequence, r.frames, r.camera, range.min_m, range.max_m, r.anchor_depth_m);
  std::cout << fmt::format("{:<16} {:>9} {:>9} {:>10} {:>9} {:>9} {:>8} {:>8} {:>5}\n", "method",
                           "ATE m", "RPE m/s", "RPE deg/s", "reg p50", "reg p95", "p50 ms",
                           "p99 ms", "lost");
  for (const auto& m : r.methods)
    std::cout << fmt::format(
        "{:<16} {:>9} {:>9} {:>10} {:>9.2f} {:>9.2f} {:>8.2f} {:>8.2f} {:>5}\n", m.name,
        cell(m.ate_rmse_m, "{:.4f}"), cell(m.rpe_t_m, "{:.4f}"), cell(m.rpe_r_deg, "{:.3f}"),
        m.reg_px_p50, m.reg_px_p95, m.p50_ms, m.p99_ms, m.lost_frames);
  const auto& first = r.methods.front();
  std::cout << fmt::format(
      "(ATE: RMSE after a rigid alignment; RPE: RMSE over {} pairs 1 s apart; reg: px between "
      "the anchor projected with the tracked and the true pose, over the {} of {} frames where "
      "the truth sees it)\n",
      first.rpe_pairs, first.reg_frames, r.frames);
}

void run(const Options& o) {
  const eval::TrackingDepthRange range;
  eval::TrackingEvalReport report;
  try {
    const auto methods =
        o.methods.empty() ? eval::tracking_method_names() : eval::parse_tracking_methods(o.methods);
    auto sequence = eval::open_tracking_sequence(o.dataset, o.frames);
    std::unique_ptr<ComputeContext> ctx;
    if (std::find(methods.begin(), methods.end(), "dense") != methods.end())
      ctx = std::make_unique<ComputeContext>();
    report = eval::evaluate_tracking(*sequence, methods, range, ctx.get());
    if (!o.trajectories.empty()) eval::write_tum_trajectories(report, o.trajectories);
    if (!o.per_frame.empty()) eval::write_per_frame_csv(report, o.per_frame);
  } catch (const std::exception& e) {
    throw CommandError(std::string("eval tracking: ") + e.what());
  }
  print(report, range);
  if (o.json.empty()) return;
  nlohmann::json methods = nlohmann::json::object();
  for (const auto& m : report.methods)
    methods[m.name] = {{"ate_rmse_m", number_or_null(m.ate_rmse_m)},
                       {"rpe_t_m", number_or_null(m.rpe_t_m)},
                       {"rpe_r_deg", number_or_null(m.rpe_r_deg)},
                       {"reg_px_p50", m.reg_px_p50},
                       {"reg_px_p95", m.reg_px_p95},
                       {"p50_ms", m.p50_ms},
                       {"p99_ms", m.p99_ms},
                       {"lost_frames", m.lost_frames}};
  write_json_report(
      o.json, {{"sequence", report.sequence}, {"frames", report.frames}, {"methods", methods}});
}

}  // namespace

void add_eval_tracking_command(CLI::App& eval) {
  auto o = std::make_shared<Options>();
  auto* cmd = eval.add_subcommand(
      "tracking", "Camera tracking against ground truth: the dense tracker and OpenCV's odometry");
  cmd->add_option("--dataset", o->dataset,
                  "tum:DIR[?calibration=FILE] (a TUM RGB-D folder) or sim[:OPTIONS] (the sim's "
                  "moving rig, trajectory=orbit by default)")
      ->required();
  cmd->add_option("--methods", o->methods,
                  "Comma-separated: dense, dense_cpu, opencv_rgbd, opencv_icp, opencv_rgbdicp "
                  "(default: all)");
  cmd->add_option("--frames", o->frames, "At most this many frames (0: all; the sim: 150)");
  cmd->add_option("--json", o->json, "Write the report as JSON");
  cmd->add_option("--trajectories", o->trajectories,
                  "Write DIR/METHOD.txt (tracked, the first frame's camera as the world) and "
                  "DIR/groundtruth.txt (in the dataset's world), TUM trajectory format");
  cmd->add_option("--per-frame", o->per_frame,
                  "Write a CSV row per frame and method: lost, reference keyframe, registration "
                  "px, rotation and translation error against the truth (both from frame 0)");
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli
