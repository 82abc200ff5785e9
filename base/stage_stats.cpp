#include "base/stage_stats.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <iterator>
#include <numeric>

namespace probeless {

double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

TimingSummary summarize(std::vector<double> samples) {
  TimingSummary s;
  s.samples = samples.size();
  if (samples.empty()) return s;
  std::sort(samples.begin(), samples.end());
  auto rank = [&](double q) {
    const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(samples.size())));
    return samples[std::clamp<std::size_t>(i, 1, samples.size()) - 1];
  };
  s.p50_ms = rank(0.50);
  s.p99_ms = rank(0.99);
  s.mean_ms = std::accumulate(samples.begin(), samples.end(), 0.0) / samples.size();
  return s;
}

void StageStats::record(const std::string& stage, double ms) {
  std::lock_guard lock(mutex_);
  Ring& r = rings_[stage];
  if (r.values.size() < window_) {
    r.values.push_back(ms);
  } else {
    r.values[r.next] = ms;
    r.next = (r.next + 1) % window_;
  }
  if (keep_all_) r.all.push_back(ms);
}

std::map<std::string, TimingSummary> StageStats::summaries() const {
  std::lock_guard lock(mutex_);
  std::map<std::string, TimingSummary> out;
  for (const auto& [name, ring] : rings_) out[name] = summarize(ring.values);
  return out;
}

std::vector<double> StageStats::all_samples(const std::string& stage) const {
  std::lock_guard lock(mutex_);
  auto it = rings_.find(stage);
  return it == rings_.end() ? std::vector<double>{} : it->second.all;
}

namespace {
constexpr std::int64_t kRateWindowNs = 2'000'000'000;
}

void RateMeter::tick(std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  ticks_.push_back(now_ns);
  const auto cut = std::find_if(ticks_.begin(), ticks_.end(),
                                [&](std::int64_t t) { return now_ns - t <= kRateWindowNs; });
  ticks_.erase(ticks_.begin(), cut);
}

double RateMeter::rate_hz(std::int64_t now_ns) const {
  std::lock_guard lock(mutex_);
  // The window ends now, not at the last tick: tick() keeps the oldest tick up to a window
  // before the newest one, and judging the whole list stale by that tick alone read 0 fps
  // for any stream slower than a few frames per second (the sim under ASan, CVF on a board).
  const auto first = std::find_if(ticks_.begin(), ticks_.end(),
                                  [&](std::int64_t t) { return now_ns - t <= kRateWindowNs; });
  const auto n = std::distance(first, ticks_.end());
  if (n < 2) return 0.0;
  const double span = static_cast<double>(ticks_.back() - *first) * 1e-9;
  return span > 0 ? static_cast<double>(n - 1) / span : 0.0;
}

}  // namespace probeless
