// probeless bench sim: how fast the synthetic rig renders, alone and as the service drives it
// (RGB-D free-running beside a fisheye paced at its frame rate, each on its own thread).
// Wall-clock numbers depend on what else the machine runs; the CPU time per frame does not
// so much, so both are printed.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "base/stage_stats.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct BenchSimOptions {
  int frames = 300;
  std::string sim;  // extra sim options, after the bench's realtime=0
  double fisheye_fps = 50;
  std::string json;
};

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

struct StreamResult {
  TimingSummary per_frame;
  double fps = 0;
  double cpu_ms_per_frame = 0;  // all threads of the process, over the run
};

// The bracket sequencer's cycle, so the fisheye sees the exposures it would in service.
ExposureStamp bracket(std::uint64_t n) {
  static constexpr double kTimes[] = {0.0005, 0.004, 0.016, 0.004};
  ExposureStamp e;
  e.cycle_position = static_cast<std::uint32_t>(n % 4);
  e.cycle = n / 4;
  e.exposure.time_s = kTimes[e.cycle_position];
  e.level = e.cycle_position == 0   ? BracketLevel::Low
            : e.cycle_position == 2 ? BracketLevel::High
                                    : BracketLevel::Medium;
  return e;
}

template <typename ReadOne>
StreamResult run_alone(int frames, ReadOne read_one) {
  std::vector<double> samples;
  const double cpu0 = process_cpu_ms();
  const auto start = Clock::now();
  for (int i = 0; i < frames; ++i) {
    const auto t0 = Clock::now();
    read_one(i);
    samples.push_back(ms_between(t0, Clock::now()));
  }
  const double wall = ms_between(start, Clock::now());
  StreamResult r;
  r.per_frame = summarize(std::move(samples));
  r.fps = frames * 1000.0 / wall;
  r.cpu_ms_per_frame = (process_cpu_ms() - cpu0) / frames;
  return r;
}

void read_or_throw(ReadResult r, const char* what) {
  if (r != ReadResult::Frame) throw CommandError(fmt::format("sim {} source stopped", what));
}

void print_stream(const std::string& label, const StreamResult& r) {
  std::cout << fmt::format("  {:<28} {:7.1f} fps  p50 {:6.2f} ms  p99 {:6.2f} ms", label, r.fps,
                           r.per_frame.p50_ms, r.per_frame.p99_ms);
  if (r.cpu_ms_per_frame > 0)
    std::cout << fmt::format("  cpu {:6.2f} ms/frame", r.cpu_ms_per_frame);
  std::cout << "\n";
}

void run(const BenchSimOptions& o) {
  const std::string spec = "realtime=0" + (o.sim.empty() ? std::string() : "," + o.sim);
  const sim::SimOptions options = sim::parse_sim_options(spec);
  const auto t_open = Clock::now();
  Rig rig = sim::make_sim_rig(options);
  const double open_ms = ms_between(t_open, Clock::now());
  std::cout << fmt::format("bench sim: {} frames, sim:{} ({} render threads per source)\n",
                           o.frames, spec, options.render_threads);
  std::cout << fmt::format("  world + rig set-up            {:7.1f} ms\n", open_ms);

  const auto timeout = std::chrono::milliseconds(1000);
  RgbdFrame rgbd;
  FisheyeFrame fisheye;
  const int warmup = std::min(10, o.frames);
  for (int i = 0; i < warmup; ++i) {
    read_or_throw(rig.rgbd->read(rgbd, timeout), "RGB-D");
    read_or_throw(rig.fisheye->read(fisheye, timeout), "fisheye");
  }
  const StreamResult rgbd_alone =
      run_alone(o.frames, [&](int) { read_or_throw(rig.rgbd->read(rgbd, timeout), "RGB-D"); });
  print_stream("RGB-D alone", rgbd_alone);
  const StreamResult fisheye_alone = run_alone(o.frames, [&](int i) {
    rig.fisheye->set_next_exposure(bracket(static_cast<std::uint64_t>(i)));
    read_or_throw(rig.fisheye->read(fisheye, timeout), "fisheye");
  });
  print_stream(fmt::format("fisheye {}px alone", options.fisheye_size), fisheye_alone);

  // Both at once: the fisheye paced at its rate on one thread, RGB-D as fast as it goes on
  // another, for o.frames RGB-D frames.
  std::atomic<bool> stop{false};
  std::atomic<int> fisheye_frames{0};
  std::vector<double> fisheye_samples;
  const double cpu0 = process_cpu_ms();
  const auto start = Clock::now();
  std::thread fisheye_thread([&] {
    const auto period = std::chrono::duration<double>(1.0 / o.fisheye_fps);
    auto due = Clock::now();
    FisheyeFrame f;
    for (std::uint64_t n = 0; !stop; ++n) {
      std::this_thread::sleep_until(due);
      const auto t0 = Clock::now();
      rig.fisheye->set_next_exposure(bracket(n));
      if (rig.fisheye->read(f, timeout) != ReadResult::Frame) break;
      fisheye_samples.push_back(ms_between(t0, Clock::now()));
      ++fisheye_frames;
      due += std::chrono::duration_cast<Clock::duration>(period);
      if (due < Clock::now()) due = Clock::now();  // late: no catching up in a burst
    }
  });
  std::vector<double> rgbd_samples;
  for (int i = 0; i < o.frames; ++i) {
    const auto t0 = Clock::now();
    read_or_throw(rig.rgbd->read(rgbd, timeout), "RGB-D");
    rgbd_samples.push_back(ms_between(t0, Clock::now()));
  }
  const double wall = ms_between(start, Clock::now());
  stop = true;
  fisheye_thread.join();
  const double cpu = process_cpu_ms() - cpu0;
  StreamResult rgbd_both, fisheye_both;
  rgbd_both.per_frame = summarize(std::move(rgbd_samples));
  rgbd_both.fps = o.frames * 1000.0 / wall;
  fisheye_both.per_frame = summarize(std::move(fisheye_samples));
  fisheye_both.fps = fisheye_frames * 1000.0 / wall;
  std::cout << fmt::format("  together (fisheye paced at {:.0f} fps), cpu {:.0f}% of one core:\n",
                           o.fisheye_fps, 100.0 * cpu / wall);
  print_stream("RGB-D", rgbd_both);
  print_stream("fisheye", fisheye_both);

  if (!o.json.empty()) {
    const auto stream = [](const StreamResult& r) {
      return nlohmann::json{{"fps", r.fps},
                            {"ms_p50", r.per_frame.p50_ms},
                            {"ms_p99", r.per_frame.p99_ms},
                            {"cpu_ms_per_frame", r.cpu_ms_per_frame}};
    };
    const nlohmann::json j{{"rgbd_fps", rgbd_both.fps},
                           {"fisheye_fps", fisheye_both.fps},
                           {"rgbd_ms_p50", rgbd_both.per_frame.p50_ms},
                           {"rgbd_ms_p99", rgbd_both.per_frame.p99_ms},
                           {"fisheye_ms_p50", fisheye_both.per_frame.p50_ms},
                           {"fisheye_ms_p99", fisheye_both.per_frame.p99_ms},
                           {"fisheye_target_fps", o.fisheye_fps},
                           {"rgbd_alone", stream(rgbd_alone)},
                           {"fisheye_alone", stream(fisheye_alone)},
                           {"cpu_percent_together", 100.0 * cpu / wall},
                           {"setup_ms", open_ms},
                           {"frames", o.frames},
                           {"sim", spec},
                           {"hardware_threads", std::thread::hardware_concurrency()}};
    write_json_report(o.json, j);
  }
}

}  // namespace

void add_bench_sim_command(CLI::App& bench) {
  auto opts = std::make_shared<BenchSimOptions>();
  auto* cmd = bench.add_subcommand("sim", "Synthetic rig render speed (RGB-D and fisheye)");
  cmd->add_option("--frames", opts->frames, "RGB-D frames per measurement")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--sim", opts->sim,
                  "Extra sim options (e.g. trajectory=static,fisheye_size=1024)");
  cmd->add_option("--fisheye-fps", opts->fisheye_fps, "Fisheye rate when both run")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--json", opts->json, "Also write the numbers to this JSON file");
  cmd->callback([opts] { run(*opts); });
}

}  // namespace probeless::cli
