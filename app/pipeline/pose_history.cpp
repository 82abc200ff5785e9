#include "app/pipeline/pose_history.hpp"

#include <algorithm>
#include <stdexcept>

namespace probeless {

PoseHistory::PoseHistory(TimestampNs hold_ns, TimestampNs max_gap_ns, std::size_t capacity)
    : hold_ns_(hold_ns), max_gap_ns_(max_gap_ns), capacity_(capacity) {
  if (hold_ns < 0 || max_gap_ns <= 0 || capacity < 2)
    throw std::invalid_argument("PoseHistory: hold >= 0, gap > 0 and capacity >= 2");
}

void PoseHistory::push(Sample s) {
  {
    std::lock_guard lock(mutex_);
    if (!samples_.empty() && s.t <= samples_.back().t) return;
    samples_.push_back(std::move(s));
    if (samples_.size() > capacity_) samples_.pop_front();
  }
  arrived_.notify_all();
}

void PoseHistory::add(TimestampNs t, const Pose& T_world_rig) {
  push({t, T_world_rig});
}

void PoseHistory::mark_unknown(TimestampNs t) {
  push({t, std::nullopt});
}

std::optional<Pose> PoseHistory::at_locked(TimestampNs t) const {
  if (samples_.empty()) return std::nullopt;
  // The first sample at or after t.
  const auto after = std::lower_bound(samples_.begin(), samples_.end(), t,
                                      [](const Sample& s, TimestampNs v) { return s.t < v; });
  if (after != samples_.end() && after->t == t) return after->pose;
  const Sample* next = after == samples_.end() ? nullptr : &*after;
  const Sample* prev = after == samples_.begin() ? nullptr : &*std::prev(after);
  if (prev && next && prev->pose && next->pose && next->t - prev->t <= max_gap_ns_)
    return interpolate(*prev->pose, *next->pose,
                       static_cast<double>(t - prev->t) / static_cast<double>(next->t - prev->t));
  // Beyond either end, or beside a loss: the nearest known pose if it is close enough, and
  // only when no loss lies between it and t (next/prev is then that very sample).
  if (prev && prev->pose && t - prev->t <= hold_ns_) return prev->pose;
  if (next && next->pose && next->t - t <= hold_ns_) return next->pose;
  return std::nullopt;
}

std::optional<Pose> PoseHistory::at(TimestampNs t) const {
  std::lock_guard lock(mutex_);
  return at_locked(t);
}

std::optional<Pose> PoseHistory::wait_at(TimestampNs t, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  arrived_.wait_for(lock, timeout, [&] { return !samples_.empty() && samples_.back().t >= t; });
  return at_locked(t);
}

std::size_t PoseHistory::size() const {
  std::lock_guard lock(mutex_);
  return samples_.size();
}

}  // namespace probeless
