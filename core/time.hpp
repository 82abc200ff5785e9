#pragma once
#include <chrono>
#include <cstdint>

namespace probeless {

// CLOCK_MONOTONIC nanoseconds (std::chrono::steady_clock on Linux). Every frame carries one;
// recordings store them as they were, replay re-bases them onto the current clock.
using TimestampNs = std::int64_t;

inline TimestampNs monotonic_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

constexpr TimestampNs ms_to_ns(std::int64_t ms) {
  return ms * 1'000'000;
}

}  // namespace probeless
