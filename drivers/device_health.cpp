#include "drivers/device_health.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

namespace probeless {

bool ReopenClock::wait_until_due(TimestampNs deadline) const {
  const TimestampNs wake = std::min(next_ns_, deadline);
  const TimestampNs now = monotonic_now_ns();
  if (wake > now) std::this_thread::sleep_for(std::chrono::nanoseconds(wake - now));
  return due();
}

}  // namespace probeless
