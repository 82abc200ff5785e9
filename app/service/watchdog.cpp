#include "app/service/watchdog.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <condition_variable>
#include <mutex>

namespace probeless {

using namespace std::chrono_literals;

std::chrono::milliseconds ServiceWatchdog::stale_after(SystemdNotifier& notifier) {
  const auto interval = notifier.watchdog_interval();
  if (!interval) return 2000ms;
  return std::max<std::chrono::milliseconds>(
      std::chrono::duration_cast<std::chrono::milliseconds>(*interval), 2000ms);
}

ServiceWatchdog::ServiceWatchdog(SystemdNotifier& notifier, HeartbeatRegistry& heartbeats)
    : notifier_(notifier), heartbeats_(heartbeats) {
  if (notifier_.watchdog_interval()) thread_ = std::jthread([this](std::stop_token s) { run(s); });
}

ServiceWatchdog::~ServiceWatchdog() = default;  // jthread: request_stop() and join

void ServiceWatchdog::run(std::stop_token stop) {
  // Half the interval systemd gave, as sd_watchdog_enabled(3) advises.
  const auto every = *notifier_.watchdog_interval() / 2;
  std::mutex mutex;
  std::condition_variable_any wake;
  std::vector<std::string> withheld_for;
  while (!stop.stop_requested()) {
    const std::vector<std::string> stale = heartbeats_.stale();
    if (stale.empty()) {
      notifier_.watchdog();
      if (!withheld_for.empty()) spdlog::info("watchdog: every thread beats again");
    } else if (stale != withheld_for) {
      spdlog::error("watchdog: no WATCHDOG=1 while {} silent for over {} ms",
                    fmt::join(stale, ", "), heartbeats_.stale_after().count());
    }
    withheld_for = stale;
    std::unique_lock lock(mutex);
    wake.wait_for(lock, stop, every, [] { return false; });
  }
}

}  // namespace probeless
