#pragma once
// What the device sources (v4l2, libcamera, openni2) share about a device that is missing or
// lost (docs/drivers.md "States"): the reason, readable from any thread, and when to look for
// the device again.
#include <mutex>
#include <string>

#include "core/time.hpp"

namespace probeless {

// A message set by the reader's thread and read by status threads.
class SharedMessage {
 public:
  std::string get() const {
    std::lock_guard lock(mutex_);
    return text_;
  }
  void set(std::string text) {
    std::lock_guard lock(mutex_);
    text_ = std::move(text);
  }

 private:
  mutable std::mutex mutex_;
  std::string text_;
};

// A look every period, counted from when the last look ended: a look that itself takes long
// (libcamera's first CameraManager start took a second under load) is not followed at once
// by another.
class ReopenClock {
 public:
  explicit ReopenClock(int period_ms) : period_ns_(ms_to_ns(period_ms)) {}
  // A look ended without the device, or the device was lost.
  void looked() { next_ns_ = monotonic_now_ns() + period_ns_; }
  TimestampNs next_ns() const { return next_ns_; }
  bool due() const { return monotonic_now_ns() >= next_ns_; }
  // Sleeps until the next look or `deadline`, whichever is first (a read waits, it does not
  // spin); true when the look is due.
  bool wait_until_due(TimestampNs deadline) const;

 private:
  TimestampNs period_ns_;
  TimestampNs next_ns_ = 0;
};

}  // namespace probeless
