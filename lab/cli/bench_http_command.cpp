// probeless bench http: the service's HTTP side under load and abuse (issue #20 item 3), from
// outside over loopback. A `probeless run` on the sim (service defaults; stream slots raised
// to take the viewers) with its descriptor limit at systemd's default soft limit (1024):
//   1. the frame rate alone, then under 64 viewers + 8 stalled viewers + 200 idle connections
//      + a slowloris of 200 (ratio = loaded / alone), and a new viewer's wait for its first
//      frame under that load;
//   2. 10,000 viewers that leave mid-frame with a reset (SO_LINGER 0);
//   3. descriptors and resident memory against the baseline taken before any client, once
//      the service's own memory has settled (wait_until_steady).
// Bar: ratio >= 0.95, new_viewer_ms <= 1000, fds and RSS back within 5 %.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "lab/bench/http_load.hpp"
#include "lab/bench/service_under_test.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kLeavingBatch = 50;  // viewers connected at once before they reset

struct BenchHttpOptions {
  lab::HttpLoadMix mix;
  int leaving = 10000;
  double seconds = 10;  // each frame-rate window
  int new_viewers = 5;  // samples of new_viewer_ms under load (the worst is reported)
  int service_nofile = 1024;
  double settle_s = 240;  // at most this long for the service's memory to settle
  std::string source = "sim";
  std::string json;
};

// Frames processed per second over `seconds`.
double frame_rate(const lab::ServiceUnderTest& service, double seconds) {
  const auto f0 = service.frames_processed();
  const auto t0 = Clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const auto f1 = service.frames_processed();
  return static_cast<double>(f1 - f0) / std::chrono::duration<double>(Clock::now() - t0).count();
}

// The service's steady state, before any client: its resident memory grows for the first
// ~40 s while the light capture makes its keyframes up to [light] max_keyframes (the sim's
// rig moves), 326 -> 498 MB without a client (2026-11-26). A baseline taken then would blame
// the HTTP load for the light's warm-up. Waits until three samples 5 s apart agree within
// 2 % (at most `timeout_s`); returns the seconds it waited.
double wait_until_steady(const lab::ServiceUnderTest& service, double timeout_s) {
  const auto start = Clock::now();
  std::vector<double> rss{service.sample().rss_mb};
  while (std::chrono::duration<double>(Clock::now() - start).count() < timeout_s) {
    std::this_thread::sleep_for(std::chrono::seconds(5));
    rss.push_back(service.sample().rss_mb);
    if (rss.size() >= 3) {
      const auto [lo, hi] = std::minmax_element(rss.end() - 3, rss.end());
      if (*hi <= *lo * 1.02) break;
    }
  }
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The median of three samples 2 s apart: the light's keyframe churn moves RSS by a few
// percent from one second to the next (malloc_trim every 10 s, app/service/heap_trim.hpp).
lab::ProcessSample median_sample(const lab::ServiceUnderTest& service) {
  std::vector<lab::ProcessSample> s;
  for (int i = 0; i < 3; ++i) {
    if (i > 0) std::this_thread::sleep_for(std::chrono::seconds(2));
    s.push_back(service.sample());
  }
  std::sort(s.begin(), s.end(), [](const auto& a, const auto& b) { return a.rss_mb < b.rss_mb; });
  return s[1];
}

// Waits until the descriptors are back at `fds` (or `timeout`): closes finish asynchronously.
lab::ProcessSample settled(const lab::ServiceUnderTest& service, int fds, double timeout_s) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  lab::ProcessSample s = service.sample();
  while (s.fds > fds && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    s = service.sample();
  }
  return s;
}

void run_bench(const BenchHttpOptions& o) {
  const long own_limit = lab::raise_descriptor_limit();
  const int needed = o.mix.viewers + o.mix.stalled + o.mix.idle + o.mix.slowloris + 200;
  if (own_limit < needed)
    throw CommandError(
        fmt::format("bench http needs {} descriptors, this process may open {} "
                    "(ulimit -Hn)",
                    needed, own_limit));
  // Service defaults, but stream slots for every viewer of the bench (32 by default: the
  // 64 viewers would otherwise be refused, and a new viewer with them).
  const auto config = std::filesystem::temp_directory_path() /
                      fmt::format("probeless-bench-http-{}.toml", getpid());
  std::ofstream(config) << fmt::format(
      "[http]\nmax_stream_clients = {}\n",
      o.mix.viewers + o.mix.stalled + o.new_viewers + kLeavingBatch + 8);
  lab::ServiceUnderTest service({"--source", o.source, "--config", config.string()}, 0,
                                o.service_nofile);
  std::filesystem::remove(config);
  std::cout << fmt::format("bench http: service pid {} port {} (LimitNOFILE {})\n", service.pid(),
                           service.port(), o.service_nofile)
            << std::flush;
  // Warm-up: the first frames build OpenCL programs.
  const auto warm_deadline = Clock::now() + std::chrono::seconds(120);
  while (service.frames_processed() < 10 && Clock::now() < warm_deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const double warmup_s = wait_until_steady(service, o.settle_s);
  const lab::ProcessSample before = median_sample(service);
  const double fps_alone = frame_rate(service, o.seconds);
  std::cout << fmt::format("  alone: {:.2f} fps, {} fds, {:.1f} MB\n", fps_alone, before.fds,
                           before.rss_mb)
            << std::flush;

  double fps_loaded = 0;
  std::vector<double> new_viewer_ms;
  int new_viewers_refused = 0;
  lab::HttpLoadCounts load_counts;
  nlohmann::json http_under_load;
  lab::ProcessSample loaded;
  {
    lab::HttpLoad load(service.port(), o.mix);
    std::this_thread::sleep_for(std::chrono::seconds(2));  // every connection made
    fps_loaded = frame_rate(service, o.seconds);
    for (int i = 0; i < o.new_viewers; ++i) {
      if (auto ms = lab::time_to_first_frame(service.port(), std::chrono::seconds(10)))
        new_viewer_ms.push_back(*ms);
      else
        ++new_viewers_refused;
    }
    loaded = service.sample();
    http_under_load = service.status()["http"];
    http_under_load.erase("stream_clients");
    load_counts = load.counts();
  }
  std::cout << fmt::format("  loaded: {:.2f} fps, {} fds, new viewer {} ms\n", fps_loaded,
                           loaded.fds,
                           new_viewer_ms.empty()
                               ? -1.0
                               : *std::max_element(new_viewer_ms.begin(), new_viewer_ms.end()))
            << std::flush;

  const auto leave_start = Clock::now();
  const int left_mid_frame =
      lab::viewers_leaving_mid_frame(service.port(), o.leaving, kLeavingBatch);
  const double leave_s = std::chrono::duration<double>(Clock::now() - leave_start).count();
  std::cout << fmt::format("  {} of {} viewers left mid-frame with a reset in {:.1f} s\n",
                           left_mid_frame, o.leaving, leave_s)
            << std::flush;
  lab::ProcessSample after = settled(service, before.fds, 15);
  after.rss_mb = median_sample(service).rss_mb;
  if (!service.alive()) throw CommandError("bench http: the service died");
  nlohmann::json http_after = service.status()["http"];
  http_after.erase("stream_clients");

  const double worst_ms =
      new_viewer_ms.empty() ? -1 : *std::max_element(new_viewer_ms.begin(), new_viewer_ms.end());
  const nlohmann::json report{
      {"fps_alone", fps_alone},
      {"fps_loaded", fps_loaded},
      {"ratio", fps_alone > 0 ? fps_loaded / fps_alone : 0},
      {"fds_before", before.fds},
      {"fds_after", after.fds},
      {"rss_before_mb", before.rss_mb},
      {"rss_after_mb", after.rss_mb},
      {"new_viewer_ms", worst_ms},
      {"details",
       {{"new_viewer_ms_samples", new_viewer_ms},
        {"new_viewers_without_a_frame", new_viewers_refused},
        {"fds_loaded", loaded.fds},
        {"rss_loaded_mb", loaded.rss_mb},
        {"threads", after.threads},
        {"load",
         {{"viewers", o.mix.viewers},
          {"stalled", o.mix.stalled},
          {"idle", o.mix.idle},
          {"slowloris", o.mix.slowloris},
          {"viewer_bytes", load_counts.viewer_bytes},
          {"viewers_closed", load_counts.viewers_closed},
          {"reconnects", load_counts.reconnects}}},
        {"leaving", {{"count", o.leaving}, {"got_bytes", left_mid_frame}, {"seconds", leave_s}}},
        {"service_nofile", o.service_nofile},
        {"warmup_s", warmup_s},
        {"http_under_load", http_under_load},
        {"http_after", http_after}}}};
  std::cout << report.dump(2) << "\n";
  if (!o.json.empty()) write_json_report(o.json, report);
}

}  // namespace

void add_bench_http_command(CLI::App& bench) {
  auto o = std::make_shared<BenchHttpOptions>();
  auto* cmd = bench.add_subcommand(
      "http",
      "The service's HTTP side under viewers, stalled viewers, idle connections, a "
      "slowloris and viewers leaving with a reset");
  cmd->add_option("--viewers", o->mix.viewers, "Viewers taking the stream (64)")
      ->check(CLI::Range(0, 10000));
  cmd->add_option("--stalled", o->mix.stalled, "Viewers that never read (8)")
      ->check(CLI::Range(0, 10000));
  cmd->add_option("--idle", o->mix.idle, "Connections that send nothing (200)")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--slowloris", o->mix.slowloris, "Connections trickling headers (200)")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--leaving", o->leaving, "Viewers that reset mid-frame (10000)")
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--seconds", o->seconds, "Each frame-rate window (10)")
      ->check(CLI::Range(0.5, 600.0));
  cmd->add_option("--service-nofile", o->service_nofile,
                  "The service's descriptor limit (1024, systemd's default soft limit)")
      ->check(CLI::Range(64, 1048576));
  cmd->add_option("--source", o->source, "The service's source (sim)");
  cmd->add_option("--settle-s", o->settle_s,
                  "Wait at most this long for the service's RSS to settle before the "
                  "baseline (240; 0: take it at once)");
  cmd->add_option("--json", o->json, "Write the report as JSON");
  cmd->callback([o] { run_bench(*o); });
}

}  // namespace probeless::cli
