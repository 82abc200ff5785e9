// probeless bench occlusion: CVF (the shipped method, or --method cvf_thesis) per 640x480 frame
// on the OpenCL device against the same method on the CPU built on OpenCV's guided filter, with the
// MSE of each on the same input so that speed never hides a quality loss (docs/occlusion.md
// "Speed"). Every timed device frame ends with queue.finish(): the numbers are what the pipeline
// waits, not enqueue time.
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>

#include "base/stage_stats.hpp"
#include "kernels/occlusion/cvf/cvf_local_reference.hpp"
#include "kernels/occlusion/cvf/cvf_matte.hpp"
#include "kernels/occlusion/cvf/cvf_reference.hpp"
#include "lab/cli/lab_commands.hpp"
#include "lab/eval/cvf_opencv_reference.hpp"
#include "lab/eval/matte_metrics.hpp"
#include "lab/eval/middlebury_dataset.hpp"

namespace probeless::cli {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string json;
  std::string scene;           // Middlebury scene directory; empty = look in the shared data
  std::string method = "cvf";  // or "cvf_thesis"
  int width = 640, height = 480;
  int frames = 200, warmup = 20, reference_frames = 30;
  int subsample = 0;       // 0 = the method's default
  int profile_frames = 0;  // > 0: that many extra frames with a per-stage breakdown
};

struct Timing {
  double p50 = 0, p99 = 0;
};

Timing percentiles(std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  auto at = [&](double q) {
    return ms[std::min(ms.size() - 1, static_cast<std::size_t>(q * ms.size()))];
  };
  return {at(0.5), at(0.99)};
}

// CPU time of the whole process (every thread: PoCL's workers included), in ms. On a shared
// machine the wall time of a frame grows with the load; the CPU time it costs does much less,
// so CPU ms per frame / cores is a floor for the wall time on an idle machine.
double process_cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return (u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 +
         (u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-3;
}

// The 1, 5 and 15 minute load averages, for the record of a shared machine.
std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return in ? a + " " + b + " " + c : std::string("unknown");
}

fs::path default_scene() {
  return find_shared_data("middlebury/2014q/Adirondack", "im0.png");
}

// A synthetic stand-in when no Middlebury data is present: textured wall at 2.2 m, a box and
// a disc in front, holes along their edges, the virtual plane slanting through them.
eval::EvalFrame synthetic_frame(int w, int h) {
  eval::EvalFrame f{ImageRGB8(w, h), DepthImage(w, h), ImageF(w, h), ImageF(w, h),
                    ImageGray8(w, h)};
  std::mt19937 rng(3);
  std::normal_distribution<float> n(0.0F, 10.0F);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool disc = std::hypot(x - 0.35F * w, y - 0.5F * h) < 0.22F * h;
      const bool box = x > 0.6F * w && x < 0.85F * w && y > 0.2F * h;
      const float z = disc ? 1200.0F : box ? 1500.0F : 2200.0F;
      const std::uint8_t base[3] = {std::uint8_t(disc  ? 200
                                                 : box ? 60
                                                       : 120),
                                    std::uint8_t(box ? 170 : 90), std::uint8_t(disc ? 40 : 150)};
      for (int c = 0; c < 3; ++c)
        f.colour.at(x, y, c) = std::uint8_t(std::clamp(base[c] + n(rng), 0.0F, 255.0F));
      const float v = 1300.0F + 400.0F * x / w;
      const bool on = x > 0.1F * w && x < 0.9F * w && y > 0.1F * h && y < 0.9F * h;
      f.virtual_depth_mm.at(x, y) = on ? v : 0.0F;
      f.truth.at(x, y) = on && z >= v ? 1.0F : 0.0F;
      f.mask.at(x, y) = on ? 255 : 0;
      f.real_depth_mm.at(x, y) = std::uint16_t(z + 0.2F * n(rng));
    }
  // Holes on the real silhouettes, as a structured-light sensor leaves them.
  DepthImage holes = f.real_depth_mm;
  for (int y = 1; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x)
      if (std::abs(int(f.real_depth_mm.at(x + 1, y)) - int(f.real_depth_mm.at(x - 1, y))) > 100)
        for (int k = -3; k <= 3; ++k) holes.at(std::clamp(x + k, 0, w - 1), y) = 0;
  f.real_depth_mm = holes;
  return f;
}

void run(const Options& o) {
  eval::EvalFrame frame;
  std::string input;
  const fs::path scene_dir = o.scene.empty() ? default_scene() : fs::path(o.scene);
  if (!scene_dir.empty()) {
    const auto scene = eval::load_middlebury_scene(scene_dir);
    auto cases = eval::middlebury_cases(scene, {1, 1});
    frame = std::move(cases.front().frames.front());  // the plane patch
    eval::crop_center(frame, o.width, o.height);
    input = fmt::format("middlebury {} (plane patch, Kinect noise seed 1), {}x{}",
                        scene_dir.string(), frame.colour.width(), frame.colour.height());
  } else {
    frame = synthetic_frame(o.width, o.height);
    input = fmt::format("synthetic {}x{}", o.width, o.height);
  }
  if (o.method != "cvf" && o.method != "cvf_thesis")
    throw CommandError("--method: expected cvf or cvf_thesis, got '" + o.method + "'");
  const bool thesis = o.method == "cvf_thesis";
  occlusion::CvfLocalParams local;
  occlusion::CvfParams params = thesis ? occlusion::CvfParams{} : local.cvf;
  if (o.subsample > 0) params.wide.subsample = o.subsample;
  local.cvf = params;

  ComputeContext ctx;
  spdlog::info("bench occlusion: {} on {} with {}", input, ctx.describe(), o.method);
  auto cvf = thesis ? std::make_unique<occlusion::CvfMatte>(ctx, params)
                    : std::make_unique<occlusion::CvfMatte>(ctx, local);
  auto& q = ctx.queue();
  DeviceImageRGB8 colour(ctx, frame.colour);
  DeviceDepthImage depth(ctx, frame.real_depth_mm);
  DeviceImageF virt(ctx, frame.virtual_depth_mm), alpha;
  std::vector<double> device_ms;
  double cpu0 = 0;
  for (int i = 0; i < o.warmup + o.frames; ++i) {
    if (i == o.warmup) cpu0 = process_cpu_ms();
    const auto t0 = Clock::now();
    cvf->process({&colour, &depth, &virt}, alpha);
    q.finish();
    if (i >= o.warmup) device_ms.push_back(ms_since(t0));
  }
  const double device_cpu_ms = (process_cpu_ms() - cpu0) / std::max(1, o.frames);
  const auto device_alpha = alpha.download(q);

  // Per-stage breakdown (profiling mode: the queue drains after every stage, so the sum is
  // somewhat above the unprofiled frame time). Median per stage over the profiled frames.
  std::vector<std::pair<std::string, double>> stages;
  if (o.profile_frames > 0) {
    cvf->set_profiling(true);
    std::vector<std::vector<double>> per_stage;
    for (int i = 0; i < 5 + o.profile_frames; ++i) {
      cvf->process({&colour, &depth, &virt}, alpha);
      if (i < 5) continue;
      const auto& times = cvf->stage_times();
      per_stage.resize(times.size());
      for (std::size_t k = 0; k < times.size(); ++k) per_stage[k].push_back(times[k].ms);
    }
    for (std::size_t k = 0; k < per_stage.size(); ++k)
      stages.emplace_back(cvf->stage_times()[k].stage, percentiles(per_stage[k]).p50);
    cvf->set_profiling(false);
  }

  std::vector<double> ref_ms;
  ImageF ref_alpha;
  double ref_cpu0 = 0;
  for (int i = 0; i < 2 + o.reference_frames; ++i) {
    if (i == 2) ref_cpu0 = process_cpu_ms();
    const auto t0 = Clock::now();
    ref_alpha = thesis ? eval::cvf_opencv_reference(frame.colour, frame.real_depth_mm,
                                                    frame.virtual_depth_mm, params)
                       : eval::cvf_local_opencv_reference(frame.colour, frame.real_depth_mm,
                                                          frame.virtual_depth_mm, local);
    if (i >= 2) ref_ms.push_back(ms_since(t0));
  }
  const double ref_cpu_ms = (process_cpu_ms() - ref_cpu0) / std::max(1, o.reference_frames);
  occlusion::CvfLocalParams exact = local;
  exact.cvf.wide.subsample = 1;
  const auto exact_alpha = thesis
                               ? occlusion::cvf_reference(frame.colour, frame.real_depth_mm,
                                                          frame.virtual_depth_mm, exact.cvf)
                                     .alpha
                               : occlusion::cvf_local_reference(frame.colour, frame.real_depth_mm,
                                                                frame.virtual_depth_mm, exact)
                                     .alpha;

  const double mse_device = eval::matte_mse(device_alpha, frame.truth, frame.mask).value_or(0);
  const double mse_ref = eval::matte_mse(ref_alpha, frame.truth, frame.mask).value_or(0);
  const double mse_exact = eval::matte_mse(exact_alpha, frame.truth, frame.mask).value_or(0);
  const auto td = percentiles(device_ms), tr = percentiles(ref_ms);
  const double speedup = tr.p50 / td.p50;

  std::cout << fmt::format("input: {}\ndevice: {}\nload average: {}\n", input, ctx.describe(),
                           load_average())
            << fmt::format("{:<34} {:>9} {:>9} {:>9} {:>10}\n", "", "p50 ms", "p99 ms", "cpu ms",
                           "MSE x1e3")
            << fmt::format(
                   "{:<34} {:>9.2f} {:>9.2f} {:>9.2f} {:>10.4f}\n",
                   fmt::format("{} (OpenCL, wide subsample {})", o.method, params.wide.subsample),
                   td.p50, td.p99, device_cpu_ms, mse_device * 1e3)
            << fmt::format("{:<34} {:>9.2f} {:>9.2f} {:>9.2f} {:>10.4f}\n",
                           "opencv reference (CPU)", tr.p50, tr.p99, ref_cpu_ms, mse_ref * 1e3)
            << fmt::format("{:<34} {:>9} {:>9} {:>9} {:>10.4f}\n",
                           thesis ? "exact reference (cvf_reference)"
                                  : "exact reference (cvf_local_reference)",
                           "-", "-", "-", mse_exact * 1e3)
            << fmt::format(
                   "speedup (p50): {:.2f}x; cpu time ratio: {:.2f}x; cvf MSE / exact MSE: "
                   "{:.4f}\n",
                   speedup, device_cpu_ms > 0 ? ref_cpu_ms / device_cpu_ms : 0.0,
                   mse_exact > 0 ? mse_device / mse_exact : 1.0)
            << "(cpu ms: CPU time per frame over all threads; / cores bounds an idle machine's "
               "wall time from below)\n";
  if (!stages.empty()) {
    double total = 0;
    std::cout << fmt::format(
        "{} stages (median of {} profiled frames, queue drained after each):\n", o.method,
        o.profile_frames);
    for (const auto& [stage, ms] : stages) {
      std::cout << fmt::format("  {:<24} {:>7.2f} ms\n", stage, ms);
      total += ms;
    }
    std::cout << fmt::format("  {:<24} {:>7.2f} ms\n", "sum", total);
  }
  if (!o.json.empty()) {
    nlohmann::json j;
    j["method"] = o.method;
    j["cvf"] = {{"p50_ms", td.p50},
                {"p99_ms", td.p99},
                {"cpu_ms", device_cpu_ms},
                {"mse", mse_device},
                {"wide_subsample", params.wide.subsample}};
    j["opencv_reference"] = {
        {"p50_ms", tr.p50}, {"p99_ms", tr.p99}, {"cpu_ms", ref_cpu_ms}, {"mse", mse_ref}};
    j["load_average"] = load_average();
    j["exact_reference"] = {{"mse", mse_exact}};
    j["speedup"] = speedup;
    for (const auto& [stage, ms] : stages) j["cvf_stages_ms"][stage] = ms;
    j["input"] = input;
    j["device"] = ctx.describe();
    write_json_report(o.json, j);
  }
}

}  // namespace

void add_bench_occlusion_command(CLI::App& bench) {
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand(
      "occlusion", "CVF occlusion per frame on the OpenCL device vs a CPU reference on OpenCV");
  cmd->add_option("--json", o->json, "Write the numbers as JSON to this file");
  cmd->add_option("--scene", o->scene,
                  "Middlebury scene directory (default: shared data's 2014q/Adirondack, "
                  "else a synthetic frame)");
  cmd->add_option("--method", o->method,
                  "cvf (the shipped CVF) or cvf_thesis (the thesis's, one colour model per frame)")
      ->capture_default_str();
  cmd->add_option("--frames", o->frames, "Timed device frames")->capture_default_str();
  cmd->add_option("--reference-frames", o->reference_frames, "Timed OpenCV frames")
      ->capture_default_str();
  cmd->add_option("--cvf-subsample", o->subsample,
                  "CVF's wide filter subsampling (1 = exact, 2 = fast guided filter; default: "
                  "cvf 1, cvf_thesis 2)");
  cmd->add_option("--profile", o->profile_frames,
                  "Also run this many frames in profiling mode (queue drained after every "
                  "stage) and print the median time per stage");
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli
