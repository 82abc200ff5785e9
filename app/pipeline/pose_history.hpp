#pragma once
// The rig poses the processing thread used, by RGB-D timestamp, for the threads that need the
// rig's pose at another time: the light thread takes the fisheye's pose at its own timestamp
// (thesis 6.2.2: the RGB-D poses interpolated to the fisheye's frames, slerp + linear).
// Thread-safe: one writer (the processing thread), any number of readers.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

#include "core/pose.hpp"
#include "core/time.hpp"

namespace probeless {

class PoseHistory {
 public:
  // `hold_ns`: how far past the newest known pose (or before the oldest) a request may be
  // and still get it: a rig moves ~1 cm in 50 ms at a walking pace, under what one keyframe
  // update smears. `max_gap_ns`: two samples further apart are not interpolated (the
  // processing thread skipped that long: the motion between is not known). `capacity`: 34 s
  // at 30 Hz (64 kB). A fisheye frame is seldom more than a few frames behind, but `bench
  // pipeline` runs the sim's RGB-D clock ~4x ahead of the fisheye's wall clock, and a history
  // that forgot the fisheye's time would pause the light load the bench is meant to carry.
  explicit PoseHistory(TimestampNs hold_ns = 50'000'000, TimestampNs max_gap_ns = 250'000'000,
                       std::size_t capacity = 1024);

  // Samples arrive in increasing time; an older or equal one is ignored.
  void add(TimestampNs t, const Pose& T_world_rig);
  // The pose was unknown at t (tracking lost): nothing is interpolated across t.
  void mark_unknown(TimestampNs t);

  // T_world_rig at t: interpolated between the two known samples around it, or the nearest
  // known one within hold_ns; nullopt when unknown.
  std::optional<Pose> at(TimestampNs t) const;
  // As at(), after waiting up to `timeout` for a sample at or after t: the processing thread
  // runs a frame or two behind the fisheye.
  std::optional<Pose> wait_at(TimestampNs t, std::chrono::milliseconds timeout) const;

  std::size_t size() const;

 private:
  struct Sample {
    TimestampNs t;
    std::optional<Pose> pose;
  };
  std::optional<Pose> at_locked(TimestampNs t) const;
  void push(Sample s);

  TimestampNs hold_ns_, max_gap_ns_;
  std::size_t capacity_;
  mutable std::mutex mutex_;
  mutable std::condition_variable arrived_;
  std::deque<Sample> samples_;
};

}  // namespace probeless
