// probeless bench soak: the service on the sim for N minutes, sampled from outside every few
// seconds (resident memory, descriptors, threads, frame rate), with the sim's RGB-D source
// dropping out for a moment every minute (`stall_every`, docs/sim.md "Fault injection"): a
// replug as the service sees it (NoSignal, then frames again). Issue #20 item 8: a leak shows
// as RSS or descriptors that climb with time or with each replug; the bar is RSS flat within 5 %.
#include <fmt/format.h>

#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "lab/bench/service_under_test.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct SoakOptions {
  double minutes = 60;
  double interval_s = 10;
  double replug_s = 60;  // one dropout per this many seconds of the sim's 30 fps stream
  double dropout_s = 2;  // how long the source is gone each time
  double warmup_s = 60;  // samples before this are reported but not in the summary
  std::string config;    // a service config; the defaults otherwise
  std::string json;
};

// Least-squares slope of y over x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  const double d = n * sxx - sx * sx;
  return d > 0 ? (n * sxy - sx * sy) / d : 0;
}

nlohmann::json summary_of(const std::vector<double>& t, const std::vector<double>& v) {
  if (v.empty()) return nullptr;
  const double first = v.front(), last = v.back();
  const double max = *std::max_element(v.begin(), v.end());
  const double min = *std::min_element(v.begin(), v.end());
  return {{"first", first},
          {"last", last},
          {"min", min},
          {"max", max},
          {"drift_pct", first > 0 ? (last - first) / first * 100 : 0},
          {"max_over_first_pct", first > 0 ? (max - first) / first * 100 : 0},
          {"slope_per_hour", slope(t, v) * 3600}};
}

void run_soak(const SoakOptions& o) {
  constexpr int kSimFps = 30;  // the sim's default RGB-D rate, which the service runs at
  const auto every = static_cast<long long>(o.replug_s * kSimFps);
  const auto gone = static_cast<long long>(o.dropout_s * kSimFps);
  const std::string source =
      fmt::format("sim:stall={}:{},stall_every={}", every, every + gone, every);
  std::vector<std::string> args{"--source", source};
  if (!o.config.empty()) args.insert(args.end(), {"--config", o.config});
  lab::ServiceUnderTest service(args);
  std::cout << fmt::format("bench soak: pid {} on port {}, source {}, {} min\n", service.pid(),
                           service.port(), source, o.minutes)
            << std::flush;

  nlohmann::json samples = nlohmann::json::array();
  std::vector<double> ts, rss, fds, threads, fps;
  const auto start = Clock::now();
  const auto end = start + std::chrono::duration<double>(o.minutes * 60);
  auto last_t = start;
  std::uint64_t last_frames = service.frames_processed();
  std::uint64_t no_signal_samples = 0;
  for (auto next = start + std::chrono::duration<double>(o.interval_s);
       next <= end + std::chrono::milliseconds(1);
       next +=
       std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.interval_s))) {
    std::this_thread::sleep_until(next);
    if (!service.alive()) throw CommandError("bench soak: the service died");
    const lab::ProcessSample p = service.sample();
    const nlohmann::json status = service.status();
    const auto now = Clock::now();
    const std::uint64_t frames = status["frames"].value("processed", std::uint64_t{0});
    const double t = std::chrono::duration<double>(now - start).count();
    const double rate = static_cast<double>(frames - last_frames) /
                        std::chrono::duration<double>(now - last_t).count();
    const std::string rgbd = status["sources"]["rgbd"].value("state", "?");
    if (rgbd != "streaming") ++no_signal_samples;
    last_t = now;
    last_frames = frames;
    samples.push_back({{"t_s", t},
                       {"rss_mb", p.rss_mb},
                       {"fds", p.fds},
                       {"threads", p.threads},
                       {"fps", rate},
                       {"cpu_s", p.cpu_s},
                       {"rgbd", rgbd}});
    std::cout << fmt::format(
                     "  {:7.0f} s  rss {:6.1f} MB  fds {:3}  threads {:2}  fps {:5.1f}  {}\n", t,
                     p.rss_mb, p.fds, p.threads, rate, rgbd)
              << std::flush;
    if (t < o.warmup_s) continue;
    ts.push_back(t);
    rss.push_back(p.rss_mb);
    fds.push_back(p.fds);
    threads.push_back(p.threads);
    fps.push_back(rate);
  }
  const nlohmann::json report{{"minutes", o.minutes},
                              {"interval_s", o.interval_s},
                              {"source", source},
                              {"replugs", static_cast<long long>(o.minutes * 60 / o.replug_s)},
                              {"samples_not_streaming", no_signal_samples},
                              {"warmup_s", o.warmup_s},
                              {"summary",
                               {{"rss_mb", summary_of(ts, rss)},
                                {"fds", summary_of(ts, fds)},
                                {"threads", summary_of(ts, threads)},
                                {"fps", summary_of(ts, fps)}}},
                              {"samples", samples}};
  std::cout << report["summary"].dump(2) << "\n";
  if (!o.json.empty()) write_json_report(o.json, report);
}

}  // namespace

void add_bench_soak_command(CLI::App& bench) {
  auto o = std::make_shared<SoakOptions>();
  auto* cmd = bench.add_subcommand(
      "soak",
      "The service on the sim for N minutes, sampled from outside (RSS, fds, threads, fps)");
  cmd->add_option("--minutes", o->minutes, "How long (default 60)")->check(CLI::PositiveNumber);
  cmd->add_option("--interval", o->interval_s, "Seconds between samples (default 10)")
      ->check(CLI::Range(0.5, 3600.0));
  cmd->add_option("--replug", o->replug_s, "Seconds between source dropouts (default 60)")
      ->check(CLI::Range(5.0, 86400.0));
  cmd->add_option("--dropout", o->dropout_s, "Seconds each dropout lasts (default 2)")
      ->check(CLI::Range(0.1, 60.0));
  cmd->add_option("--warmup", o->warmup_s, "Seconds left out of the summary (default 60)")
      ->check(CLI::Range(0.0, 86400.0));
  cmd->add_option("--config", o->config, "Service config (default: the service's defaults)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--json", o->json, "Write the samples and summary as JSON");
  cmd->callback([o] {
    if (o->dropout_s >= o->replug_s) throw CommandError("--dropout must be shorter than --replug");
    run_soak(*o);
  });
}

}  // namespace probeless::cli
