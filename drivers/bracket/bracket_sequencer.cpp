#include "drivers/bracket/bracket_sequencer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace probeless {

double max_integration_time(const BracketConfig& config) {
  double t = config.max_time_s;
  if (config.mains_hz > 0) t = std::min(t, 1.0 / config.mains_hz);
  return t;
}

Exposure split_exposure(double exposure_value, const BracketConfig& config) {
  const double t_max = max_integration_time(config);
  Exposure e;
  if (exposure_value <= t_max) {
    e.time_s = std::max(exposure_value, config.min_time_s);
    e.gain_db = 0.0;
    return e;
  }
  e.time_s = t_max;
  e.gain_db = std::min(gain_db_from_linear(exposure_value / t_max), config.max_gain_db);
  return e;
}

BracketSequencer::BracketSequencer(const BracketConfig& config) : config_(config) {
  if (config.initial_exposure <= 0 || config.min_time_s <= 0 ||
      max_integration_time(config) < config.min_time_s)
    throw std::invalid_argument("BracketSequencer: exposure range");
  const double e_min = config.min_time_s;
  const double e_max = max_integration_time(config) * std::pow(10.0, config.max_gain_db / 20.0);
  min_stop_ = static_cast<int>(std::ceil(std::log2(e_min / config.initial_exposure) - 1e-9));
  max_stop_ = static_cast<int>(std::floor(std::log2(e_max / config.initial_exposure) + 1e-9));
  const int sp = std::max(0, config.min_spacing_stops);
  if (max_stop_ - min_stop_ < 2 * sp)
    throw std::invalid_argument("BracketSequencer: range too narrow for the spacing");
  stop_[1] = std::clamp(0, min_stop_ + sp, max_stop_ - sp);
  const int spread = std::max(sp, config.initial_spread_stops);
  stop_[0] = std::max(min_stop_, stop_[1] - spread);
  stop_[2] = std::min(max_stop_, stop_[1] + spread);
  low_fraction_.assign(static_cast<std::size_t>(max_stop_ - min_stop_ + 1), -1.0);
}

void BracketSequencer::record_low_fraction(int stop, double fraction) {
  for (int s = min_stop_; s <= max_stop_; ++s) {
    double& f = low_fraction_[static_cast<std::size_t>(s - min_stop_)];
    if (s == stop)
      f = fraction;
    else if (s > stop && f >= 0 && f < fraction)
      f = fraction;  // brighter than when that stop was seen
    else if (s < stop && f > fraction)
      f = fraction;
  }
}

int BracketSequencer::bulk_low_stop() const {
  int best = stop_[0];
  for (int s = stop_[0]; s <= max_stop_; ++s) {
    const double f = low_fraction_[static_cast<std::size_t>(s - min_stop_)];
    if (f >= 0 && f <= config_.medium_saturated_fraction) best = s;
  }
  return best;
}

double BracketSequencer::exposure_value(int stop) const {
  return config_.initial_exposure * std::ldexp(1.0, stop);
}

int BracketSequencer::stop_of(const Exposure& e) const {
  return static_cast<int>(std::lround(std::log2(e.value() / config_.initial_exposure)));
}

ExposureStamp BracketSequencer::next() {
  static constexpr BracketLevel kCycle[4] = {BracketLevel::Low, BracketLevel::Medium,
                                             BracketLevel::High, BracketLevel::Medium};
  static constexpr int kIndex[4] = {0, 1, 2, 1};
  ExposureStamp s;
  s.cycle_position = static_cast<std::uint32_t>(frame_ % 4);
  s.cycle = frame_ / 4;
  s.level = kCycle[s.cycle_position];
  s.exposure = split_exposure(exposure_value(stop_[kIndex[s.cycle_position]]), config_);
  ++frame_;
  return s;
}

bool BracketSequencer::observe(const ExposureStamp& taken, const ExposureStats& stats) {
  if (taken.level == BracketLevel::Fixed || stats.pixels == 0) return false;
  const int index = taken.level == BracketLevel::Low      ? 0
                    : taken.level == BracketLevel::Medium ? 1
                                                          : 2;
  if (stop_of(taken.exposure) != stop_[index]) return false;  // stale: already moved
  const int sp = std::max(0, config_.min_spacing_stops);
  const double n = static_cast<double>(stats.pixels);
  const double sat_limit = config_.saturated_fraction_threshold * n;
  const double zero_limit = config_.zero_fraction_threshold * n;
  int& low = stop_[0];
  int& med = stop_[1];
  int& high = stop_[2];
  switch (taken.level) {
    case BracketLevel::Low:
      record_low_fraction(low, static_cast<double>(stats.saturated) / n);
      // Thesis ch. 5: one stop down while too many saturate, one up when none do.
      if (stats.saturated > sat_limit && low > min_stop_) {
        --low;
        return true;
      }
      if (stats.saturated == 0 && stats.near_saturated <= sat_limit && low + 1 <= med - sp) {
        ++low;
        return true;
      }
      return false;
    case BracketLevel::High:
      if (stats.zero > zero_limit && high < max_stop_) {
        ++high;
        return true;
      }
      if (stats.zero == 0 && stats.near_zero <= zero_limit && high - 1 >= med + sp) {
        --high;
        return true;
      }
      return false;
    case BracketLevel::Medium: {
      // Slowly towards the middle of the bulk's L and H, once per cycle (its second frame).
      if (!config_.adapt_medium || taken.cycle_position != 3) return false;
      const auto period = static_cast<std::int64_t>(std::max(1, config_.medium_period_cycles));
      if (static_cast<std::int64_t>(taken.cycle) < medium_last_move_cycle_ + period) return false;
      const int target = static_cast<int>(std::floor((bulk_low_stop() + high) / 2.0));
      int step = target > med ? 1 : target < med ? -1 : 0;
      const int moved = med + step;
      if (step == 0 || moved < low + sp || moved > high - sp) return false;
      med = moved;
      medium_last_move_cycle_ = static_cast<std::int64_t>(taken.cycle);
      return true;
    }
    case BracketLevel::Fixed:
      break;
  }
  return false;
}

}  // namespace probeless
