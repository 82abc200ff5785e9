// probeless bench tracking: time per 640x480 RGB-D frame of the shipped dense tracker, and of
// OpenCV's odometry on the same frames for comparison (issue #17 item 6; docs/tracking.md
// "Benchmark"). Frames are read and undistorted before the clock starts, so the numbers are
// the trackers' alone.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "base/stage_stats.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "lab/cli/lab_commands.hpp"
#include "lab/eval/tracking_dataset.hpp"
#include "lab/eval/tracking_methods.hpp"

namespace probeless::cli {
namespace {

// ~1.5 MB per frame held in memory: 1000 frames is 1.5 GB, the most a bench should take.
constexpr int kMaxFrames = 1000;
constexpr int kWarmupFrames = 10;  // OpenCL program builds, first allocations

struct Options {
  std::string dataset, methods = "dense,opencv_rgbd,opencv_icp,opencv_rgbdicp", json;
  int frames = 150;
};

struct MethodTiming {
  std::string name;
  double p50_ms = 0, p99_ms = 0, cpu_ms = 0;
  int lost = 0;
};

MethodTiming time_method(eval::TrackingMethod& method,
                         const std::vector<eval::TrackingFrame>& frames) {
  for (int i = 0; i < std::min<int>(kWarmupFrames, static_cast<int>(frames.size())); ++i)
    method.track(frames[i].colour, frames[i].depth_mm, frames[i].timestamp_ns);
  method.reset();
  MethodTiming t{method.name()};
  std::vector<double> ms;
  double cpu0 = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto step = method.track(frames[i].colour, frames[i].depth_mm, frames[i].timestamp_ns);
    // The first frame only initialises (a keyframe, or nothing for OpenCV): not timed.
    if (i == 0) {
      cpu0 = process_cpu_ms();
      continue;
    }
    ms.push_back(ms_since(t0));
    t.lost += step.lost ? 1 : 0;
  }
  const TimingSummary s = summarize(ms);
  t.p50_ms = s.p50_ms;
  t.p99_ms = s.p99_ms;
  t.cpu_ms = (process_cpu_ms() - cpu0) / std::max<double>(1, static_cast<double>(ms.size()));
  return t;
}

// The shared data's fr1/rpy when it is there (real Kinect frames), else the sim's orbit.
std::string default_dataset() {
  const auto dir = find_shared_data("rgbd/tum_fr1_rpy", "rgb.txt");
  return dir.empty() ? "sim" : "tum:" + dir.string();
}

void run(const Options& o) {
  if (o.frames < 2 || o.frames > kMaxFrames)
    throw CommandError(fmt::format("bench tracking: --frames must be in 2..{}", kMaxFrames));
  std::vector<eval::TrackingFrame> frames;
  std::vector<MethodTiming> timings;
  std::string name, device;
  PinholeIntrinsics camera;
  try {
    const auto names = eval::parse_tracking_methods(o.methods);
    auto sequence =
        eval::open_tracking_sequence(o.dataset.empty() ? default_dataset() : o.dataset, o.frames);
    name = sequence->name();
    camera = sequence->camera();
    const double readout_s = sequence->rolling_shutter_readout_s();
    while (auto f = sequence->next()) frames.push_back(std::move(*f));
    if (frames.size() < 2) throw std::invalid_argument(name + ": fewer than 2 frames");
    std::unique_ptr<ComputeContext> ctx;
    if (std::find(names.begin(), names.end(), "dense") != names.end()) {
      ctx = std::make_unique<ComputeContext>();
      device = ctx->describe();
    }
    for (const auto& n : names) {
      auto method =
          eval::make_tracking_method(n, camera, eval::TrackingDepthRange{}, ctx.get(), readout_s);
      spdlog::info("bench tracking: {} on {} frames", n, frames.size());
      timings.push_back(time_method(*method, frames));
    }
  } catch (const std::exception& e) {
    throw CommandError(std::string("bench tracking: ") + e.what());
  }

  std::cout << fmt::format("bench tracking: {}, {} frames of {}x{}{}\n", name, frames.size(),
                           camera.width, camera.height, device.empty() ? "" : "; device " + device)
            << fmt::format("{:<16} {:>8} {:>8} {:>8} {:>5}\n", "method", "p50 ms", "p99 ms",
                           "cpu ms", "lost");
  const MethodTiming* dense = nullptr;
  const MethodTiming* fastest_opencv = nullptr;
  nlohmann::json methods = nlohmann::json::object();
  for (const auto& t : timings) {
    std::cout << fmt::format("{:<16} {:>8.2f} {:>8.2f} {:>8.2f} {:>5}\n", t.name, t.p50_ms,
                             t.p99_ms, t.cpu_ms, t.lost);
    methods[t.name] = {
        {"p50_ms", t.p50_ms}, {"p99_ms", t.p99_ms}, {"cpu_ms", t.cpu_ms}, {"lost_frames", t.lost}};
    if (t.name == "dense") dense = &t;
    if (t.name.starts_with("opencv_") && (!fastest_opencv || t.p50_ms < fastest_opencv->p50_ms))
      fastest_opencv = &t;
  }
  std::cout << "(cpu ms: process CPU time per frame over all threads, PoCL's included)\n";
  if (o.json.empty()) return;
  nlohmann::json j{{"sequence", name},
                   {"frames", frames.size()},
                   {"width", camera.width},
                   {"height", camera.height},
                   {"methods", methods}};
  if (dense) {
    j["p50_ms"] = dense->p50_ms;
    j["p99_ms"] = dense->p99_ms;
    j["cpu_ms"] = dense->cpu_ms;
    j["device"] = device;
  }
  if (fastest_opencv)
    j["fastest_opencv"] = {{"method", fastest_opencv->name},
                           {"p50_ms", fastest_opencv->p50_ms},
                           {"p99_ms", fastest_opencv->p99_ms},
                           {"cpu_ms", fastest_opencv->cpu_ms}};
  write_json_report(o.json, j);
}

}  // namespace

void add_bench_tracking_command(CLI::App& bench) {
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand(
      "tracking", "Time per RGB-D frame of the dense tracker and of OpenCV's odometry");
  cmd->add_option("--dataset", o->dataset,
                  "tum:DIR[?calibration=FILE] or sim[:OPTIONS] (frames held in memory; default: "
                  "the shared data's rgbd/tum_fr1_rpy, else sim)");
  cmd->add_option("--methods", o->methods,
                  "Comma-separated (dense, dense_cpu, opencv_rgbd, opencv_icp, opencv_rgbdicp)")
      ->capture_default_str();
  cmd->add_option("--frames", o->frames, "Frames to time (2..1000)")->capture_default_str();
  cmd->add_option("--json", o->json,
                  "Write {p50_ms, p99_ms, cpu_ms} of dense, the fastest OpenCV method's and "
                  "every method's as JSON");
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli
