#pragma once
// Per-stage timings over a sliding window, and frame counters: what /status, the logs and
// `probeless bench pipeline` report. Thread-safe; recording is a mutex and a ring write.
#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace probeless {

struct TimingSummary {
  double p50_ms = 0;
  double p99_ms = 0;
  double mean_ms = 0;
  std::size_t samples = 0;
};

// p50/p99 by nearest rank over a copy of the samples (a window of a few hundred: cheap).
TimingSummary summarize(std::vector<double> samples_ms);
// CPU time of the whole process (all threads) in ms: benchmarks divide it by frames, a figure
// that moves less than wall-clock time when other work shares the cores.
double process_cpu_ms();

// Milliseconds of the steady clock since `t0`: the unit every stage time is recorded in.
inline double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

class StageStats {
 public:
  // 300 samples = 5 s at 60 fps: long enough for a stable p99, short enough to follow change.
  explicit StageStats(std::size_t window = 300) : window_(window) {}

  void record(const std::string& stage, double ms);
  std::map<std::string, TimingSummary> summaries() const;
  // Every sample ever recorded for a stage, for benchmarks that need the whole run.
  void keep_all(bool on) { keep_all_ = on; }
  std::vector<double> all_samples(const std::string& stage) const;

 private:
  struct Ring {
    std::vector<double> values;
    std::size_t next = 0;
    std::vector<double> all;
  };
  std::size_t window_;
  bool keep_all_ = false;
  mutable std::mutex mutex_;
  std::map<std::string, Ring> rings_;
};

// Frames per second over a sliding window of timestamps.
class RateMeter {
 public:
  void tick(std::int64_t now_ns);
  double rate_hz(std::int64_t now_ns) const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::int64_t> ticks_;  // last ~2 s
};

}  // namespace probeless
