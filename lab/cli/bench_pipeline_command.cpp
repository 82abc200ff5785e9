// `probeless bench pipeline`: the sim through the whole pipeline (capture, render, occlusion,
// composite, download, JPEG) as fast as it goes, no frame dropped; prints fps and per-stage
// p50/p99.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string_view>
#include <thread>

#include "app/outputs/output.hpp"
#include "app/pipeline/pipeline.hpp"
#include "base/stage_stats.hpp"
#include "drivers/rig_factory.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {

struct BenchArgs {
  // RGB-D as fast as the sim renders it; the fisheye at 50 frames/s of wall-clock time, the
  // load the upward camera puts on the appliance (docs/performance.md).
  std::string source = "sim:realtime=0,fisheye_realtime=1,fisheye_fps=50,trajectory=orbit";
  // The service's defaults unless told otherwise: what a unit ships with is what is timed.
  std::string occlusion = ServiceConfig{}.occlusion_method;
  std::string tracking = ServiceConfig{}.tracking.method;
  std::string tracking_device = ServiceConfig{}.tracking.device;
  std::int64_t frames = 300;
  std::int64_t warmup = 30;
  std::string json_path;
  std::string config_path;  // objects, materials, [ground], [light] from a service config
  // The sim's frames rendered before timing (SimOptions::prerender): the pipeline's own cost,
  // as with a camera, whose frames arrive by DMA. Off: the sim renders while it is timed.
  bool prerender = false;
};

// The MJPEG stream's share of the work without a port to serve it on: the service streams by
// default, so the benchmark encodes each frame once as the service would, and drops it.
class JpegSink final : public Output {
 public:
  explicit JpegSink(int quality) : quality_(quality) {}
  std::string_view name() const override { return "jpeg_sink"; }
  OutputNeeds needs() const override { return {.jpeg = true, .jpeg_quality = quality_}; }
  void offer(const OutputFrame&) override {}
  void stop() override {}

 private:
  int quality_;
};

// CPU time per thread group so far (ms), from /proc/self/task/*/schedstat (ns on the CPU):
// the pipeline names its threads pl-* (app/pipeline/thread_name.hpp); Mesa's are llvmpipe-N;
// the rest are PoCL's workers (every OpenCL kernel: matte, composite, light update; they take
// the name of the thread that built the first context, so the pipeline names its threads
// after that) and the main thread, which sleeps. The sim's render workers are sim-pool: the
// synthetic cameras' cost (the fisheye's exposure and noise, live rendering), not the
// pipeline's, though it runs on the same two cores.
std::map<std::string, double> cpu_ms_by_thread() {
  std::map<std::string, double> out;
  std::error_code ec;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", ec)) {
    std::ifstream comm_file(task.path() / "comm"), sched_file(task.path() / "schedstat");
    std::string comm;
    double ns = 0;
    if (!std::getline(comm_file, comm) || !(sched_file >> ns)) continue;  // ended meanwhile
    std::string group = "pocl";
    if (comm.starts_with("pl-"))
      group = comm.substr(3);
    else if (comm.starts_with("llvmpipe"))
      group = "llvmpipe";
    else if (comm.starts_with("sim-"))
      group = "sim";
    out[group] += ns * 1e-6;
  }
  return out;
}

// Frames processed after the timed ones, so that timing ends in the steady state.
constexpr std::int64_t kTail = 10;
// The fisheye's prerendered scenes: a multiple of the bracket cycle's 4 frames, so each scene
// keeps one exposure level and the kept exposed frames stay 24 (150 MB at 1024 px).
constexpr int kFisheyeScenes = 24;

void run_bench(const BenchArgs& args) {
  ServiceConfig config =
      args.config_path.empty() ? ServiceConfig{} : load_service_config(args.config_path);
  config.source = args.source;
  if (args.prerender) {
    if (!config.source.starts_with("sim"))
      throw CommandError("bench pipeline: --prerender needs a sim source");
    // Every RGB-D frame the run asks for, and as many fisheye frames, served again from the
    // first once used up (fisheye_repeat): the fisheye runs on 50 frames/s of wall time, so
    // below 50 RGB-D fps it outran them and the sim's live ray casting (7-20 ms a frame) was
    // measured as the pipeline's, which slowed it further (docs/performance.md). The fisheye
    // cycles 24 scenes and keeps them exposed (fisheye_scenes, docs/sim.md): its sensor model
    // was ~5 CPU-ms a frame of the sim's, not the appliance's. The RGB-D frames carry the time
    // they are read (stamp_on_read): on the 30 Hz sim clock a pipeline below 30 fps fell
    // behind the wall-time fisheye and its light thread starved of poses.
    config.source += (config.source.find(':') == std::string::npos ? ":" : ",") +
                     fmt::format("prerender={},fisheye_repeat=1,fisheye_scenes={},stamp_on_read=1",
                                 args.frames + args.warmup + kTail, kFisheyeScenes);
  }
  config.occlusion_method = args.occlusion;
  config.tracking.method = args.tracking;
  config.tracking.device = args.tracking_device;
  config.max_frames = args.frames + args.warmup + kTail;
  PipelineOptions options;
  options.lossless = true;
  options.serve_http = false;
  options.outputs.push_back(std::make_shared<JpegSink>(config.http.jpeg_quality));
  Pipeline pipeline(config, open_rig(config.source), options);
  pipeline.start();
  if (!pipeline.wait_first_frame(std::chrono::minutes(2)))
    throw CommandError("bench pipeline: no frame came out" +
                       pipeline.fatal_error().value_or(" (timeout)"));
  // Time the frames after the warm-up (program builds, first allocations, caches).
  while (pipeline.frames_out() < static_cast<std::uint64_t>(args.warmup) && !pipeline.finished())
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const auto out0 = pipeline.frames_out();
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = process_cpu_ms();
  const auto threads0 = cpu_ms_by_thread();
  // The timed frames end while the pipeline still runs (kTail): the threads are all there to
  // be read, and the last frames are timed in the steady state, not while it drains.
  const auto last = static_cast<std::uint64_t>(args.warmup + args.frames);
  while (pipeline.frames_out() < last && !pipeline.finished())
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto out = std::min(pipeline.frames_out(), last) - out0;
  const double cpu_ms = process_cpu_ms() - cpu0;
  const auto threads1 = cpu_ms_by_thread();
  pipeline.wait_finished(std::chrono::hours(1));
  const nlohmann::json light = pipeline.status().value("light", nlohmann::json::object());
  pipeline.stop();
  if (auto err = pipeline.fatal_error()) throw CommandError(*err);

  nlohmann::json j;
  j["fps"] = static_cast<double>(out) / seconds;
  j["frames"] = out;
  // All threads (sim, render, OpenCL, encode): on N cores the pipeline cannot beat
  // N * 1000 / cpu_ms_per_frame fps, whatever else the machine does.
  j["cpu_ms_per_frame"] = out ? cpu_ms / static_cast<double>(out) : 0.0;
  // Where it went (the fisheye thread includes the sim's exposure of its frames, which a
  // camera does not cost; the light's per frame depends on the fps: it runs 50 times a second).
  nlohmann::json by_thread = nlohmann::json::object();
  for (const auto& [group, ms] : threads1) {
    const auto before = threads0.find(group);
    const double spent = ms - (before == threads0.end() ? 0.0 : before->second);
    by_thread[group] = out ? spent / static_cast<double>(out) : 0.0;
  }
  j["cpu_ms_per_frame_by_thread"] = by_thread;
  j["source"] = config.source;
  // The light thread's load is per second of wall time (the fisheye runs at 50 frames/s of
  // it), not per RGB-D frame: say how much of it the run carried.
  j["light_frames"] = light.value("frames", 0);
  j["light_dropped"] = light.value("dropped", 0);
  j["occlusion"] = args.occlusion;
  j["tracking"] = args.tracking;
  j["tracking_device"] = args.tracking_device;
  nlohmann::json stages = nlohmann::json::object();
  for (const char* name :
       {"capture_rgbd", "capture_fisheye", "exposure_count", "light", "light_publish", "tracking",
        "render", "upload", "occlusion", "composite", "download", "frame", "encode"}) {
    auto samples = pipeline.stats().all_samples(name);
    if (samples.empty()) continue;
    // light_publish runs at 4 Hz: a warm-up of frames would leave none of its samples.
    const std::size_t warmup =
        std::string_view(name) == "light_publish" ? 1 : static_cast<std::size_t>(args.warmup);
    if (samples.size() > warmup) samples.erase(samples.begin(), samples.begin() + warmup);
    const auto s = summarize(samples);
    stages[name] = {{"p50_ms", s.p50_ms}, {"p99_ms", s.p99_ms}};
  }
  j["stages"] = stages;
  j["p50_ms"] = stages.contains("frame") ? stages["frame"]["p50_ms"].get<double>() : 0.0;
  j["p99_ms"] = stages.contains("frame") ? stages["frame"]["p99_ms"].get<double>() : 0.0;

  std::cout << fmt::format("pipeline: {:.1f} fps over {} frames ({}; occlusion {}, tracking {})\n",
                           j["fps"].get<double>(), out, config.source, args.occlusion,
                           args.tracking);
  std::cout << fmt::format("  light: {} fisheye frames processed, {} dropped (whole run)\n",
                           j["light_frames"].get<std::uint64_t>(),
                           j["light_dropped"].get<std::uint64_t>());
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  std::cout << fmt::format("  cpu {:.2f} ms/frame over all threads ({} cores: <= {:.0f} fps)\n",
                           j["cpu_ms_per_frame"].get<double>(), cores,
                           cores * 1000.0 / std::max(j["cpu_ms_per_frame"].get<double>(), 1e-3));
  std::cout << "  cpu ms/frame by thread:";
  for (const auto& [group, ms] : by_thread.items())
    std::cout << fmt::format(" {} {:.2f}", group, ms.get<double>());
  std::cout << "\n";
  std::cout << fmt::format("  {:<16} {:>8} {:>8}\n", "stage", "p50 ms", "p99 ms");
  for (const auto& [name, s] : stages.items())
    std::cout << fmt::format("  {:<16} {:>8.2f} {:>8.2f}\n", name, s["p50_ms"].get<double>(),
                             s["p99_ms"].get<double>());
  if (!args.json_path.empty()) {
    std::ofstream f(args.json_path);
    f << j.dump(2) << "\n";
    if (!f) throw CommandError("cannot write " + args.json_path);
  }
}

}  // namespace

void add_bench_pipeline_command(CLI::App& bench) {
  auto args = std::make_shared<BenchArgs>();
  auto* cmd = bench.add_subcommand("pipeline", "Whole pipeline on the sim: fps, per-stage ms");
  cmd->add_option("--frames", args->frames, "Frames timed (after the warm-up)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--warmup", args->warmup, "Frames before timing starts");
  cmd->add_option("--source", args->source, "Rig spec");
  cmd->add_option("--occlusion", args->occlusion, "Occlusion method (default: the service's)");
  cmd->add_option("--tracking", args->tracking,
                  "Tracking method: dense | truth | off (default: the service's)");
  cmd->add_option("--tracking-device", args->tracking_device,
                  "Where dense tracking runs: cpu | opencl (default: the service's)");
  cmd->add_option("--json", args->json_path, "Also write the numbers as JSON");
  cmd->add_flag("--prerender", args->prerender,
                "Render the sim's frames before timing: the pipeline alone, as with a camera");
  cmd->add_option("--config", args->config_path,
                  "Service config for the scene (objects, [ground], [light]); source and "
                  "occlusion still come from the options");
  cmd->callback([args] { run_bench(*args); });
}

}  // namespace probeless::cli
