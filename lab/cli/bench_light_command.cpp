// probeless bench light: per fisheye frame, the time of upload + keyframe update (with the HDR
// conversion of the samples it reads) + push-pull + SH (LightEstimator), waiting for the queue
// after each stage
// (docs/light-capture.md, docs/performance.md "Light capture: bench light").
#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "base/stage_stats.hpp"
#include "core/exposure_count.hpp"
#include "drivers/bracket/bracket_sequencer.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "kernels/light/light_estimator.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {

struct Options {
  int frames = 120;
  std::string sim = "fisheye_size=1024";
  int face_size = 128;  // issue #5's bar (p50 <= 3 ms) is at 128; the service runs 192
  std::string json;
  bool room = false;  // parallax with the sim's room box
};

void run(const Options& o) {
  const sim::SimOptions sim_options = sim::parse_sim_options("realtime=0," + o.sim);
  Rig rig = sim::make_sim_rig(sim_options);
  ComputeContext ctx;
  light::LightEstimatorConfig config;
  config.keyframes.face_size = o.face_size;
  if (o.room) {  // as the service runs the sim with room = "sim": SH at the object
    config.room = rig.scene.room;
    config.sh_position = sim::light_probe_position();
  }
  light::LightEstimator estimator(ctx, *rig.calibration.fisheye, rig.calibration.T_rig_fisheye,
                                  config);
  BracketSequencer sequencer;
  FisheyeFrame frame;
  const int warmup = 8;
  std::cout << fmt::format(
      "bench light: 2 x {} frames of a {} px fisheye (sim:{}), {} px faces, parallax {}, {}\n",
      o.frames, sim_options.fisheye_size, o.sim, o.face_size, o.room ? "on" : "off",
      ctx.describe());
  // Frames alternate: even ones run as the service runs them (one wait per frame, at the SH
  // download), which gives the headline total; odd ones wait after each stage, which gives
  // the breakdown (and a total that includes three more waits for the queue).
  std::vector<double> total_ms, total_cpu_ms, staged_ms, staged_cpu_ms;
  StageStats stats;  // per step: its wall-clock time as NAME, its CPU time as "cpu:NAME"
  stats.keep_all(true);
  for (int i = 0; i < warmup + 2 * o.frames; ++i) {
    const ExposureStamp stamp = sequencer.next();
    rig.fisheye->set_next_exposure(stamp);
    if (rig.fisheye->read(frame, std::chrono::milliseconds(5000)) != ReadResult::Frame ||
        !frame.truth || !frame.truth->rig_pose)
      throw CommandError("bench light: the sim's fisheye stopped");
    const bool staged = i % 2 == 1;
    estimator.set_time_stages(staged);
    estimator.process(frame, *frame.truth->rig_pose);  // timed inside
    const light::LightTimings& t = estimator.last_timings();
    for (const light::LightStepTime& step : t.steps) {
      stats.record(std::string(step.step), step.wall_ms);
      stats.record("cpu:" + std::string(step.step), step.cpu_ms);
    }
    if (i >= warmup) {
      (staged ? staged_ms : total_ms).push_back(t.total.wall_ms);
      (staged ? staged_cpu_ms : total_cpu_ms).push_back(t.total.cpu_ms);
    }
    sequencer.observe(frame.exposure,
                      count_exposure(frame.raw, frame.bit_depth, frame.black_level));
  }
  // Every staged sample after the warm-up frames (compiling, first allocations).
  const auto timed = [&](const char* stage) {
    std::vector<double> all = stats.all_samples(stage);
    all.erase(all.begin(), all.begin() + std::min<std::ptrdiff_t>(warmup / 2, std::ssize(all)));
    return summarize(std::move(all));
  };
  const TimingSummary total = summarize(total_ms), total_cpu = summarize(total_cpu_ms);
  const TimingSummary staged = summarize(staged_ms), staged_cpu = summarize(staged_cpu_ms);
  nlohmann::json stages;
  const auto line = [](const std::string& name, const TimingSummary& s, const TimingSummary& cpu) {
    std::cout << fmt::format("  {:<14} p50 {:6.3f} ms  p99 {:6.3f} ms   cpu p50 {:6.3f} ms\n", name,
                             s.p50_ms, s.p99_ms, cpu.p50_ms);
  };
  line("total", total, total_cpu);
  line("staged total", staged, staged_cpu);
  for (const std::string stage : {"upload", "update", "push_pull", "sh"}) {
    const TimingSummary s = timed(stage.c_str());
    const TimingSummary cpu = timed(("cpu:" + stage).c_str());
    stages[stage] = {{"p50_ms", s.p50_ms}, {"p99_ms", s.p99_ms}, {"cpu_p50_ms", cpu.p50_ms}};
    line(stage, s, cpu);
  }
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) == 3)
    std::cout << fmt::format("  load average {:.2f} {:.2f} {:.2f}\n", load[0], load[1], load[2]);
  if (!o.json.empty()) {
    const nlohmann::json j{
        {"p50_ms", total.p50_ms},
        {"p99_ms", total.p99_ms},
        {"cpu_p50_ms", total_cpu.p50_ms},
        {"stages", stages},
        {"staged_total",
         {{"p50_ms", staged.p50_ms}, {"p99_ms", staged.p99_ms}, {"cpu_p50_ms", staged_cpu.p50_ms}}},
        {"frames", o.frames},
        {"fisheye_size", sim_options.fisheye_size},
        {"face_size", o.face_size},
        {"room_box", o.room},
        {"load_average", {load[0], load[1], load[2]}},
        {"device", ctx.describe()}};
    write_json_report(o.json, j);
  }
}

}  // namespace

void add_bench_light_command(CLI::App& bench) {
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand(
      "light", "Per fisheye frame: HDR conversion + keyframe update + push-pull + SH");
  cmd->add_option("--frames", o->frames,
                  "Frames timed each way (after 8 of warm-up): as the service runs them, and "
                  "waiting after each stage")
      ->capture_default_str();
  cmd->add_option("--sim", o->sim, "Sim options (after realtime=0)")->capture_default_str();
  cmd->add_option("--face-size", o->face_size,
                  "Keyframe face size (issue #5's bar is at 128; the service's [light] "
                  "face_size is 192)")
      ->capture_default_str();
  cmd->add_flag("--room-box", o->room,
                "Parallax with the sim's room box, SH reprojected to the object (as the "
                "service with [light] room = \"sim\")");
  cmd->add_option("--json", o->json, "Write {p50_ms, p99_ms, stages} as JSON");
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli
