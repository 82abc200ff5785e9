#pragma once
// systemd's watchdog fed from the heartbeats of every thread that matters
// (app/service/heartbeat.hpp): WATCHDOG=1 every half WatchdogSec while all of them are
// fresh, none while one is stale, so that systemd restarts a service with any of them
// wedged (issue #20 item 6). Nothing to do without WATCHDOG_USEC.
#include <stop_token>
#include <string>
#include <thread>

#include "app/service/heartbeat.hpp"
#include "app/service/systemd_notifier.hpp"

namespace probeless {

class ServiceWatchdog {
 public:
  ServiceWatchdog(SystemdNotifier& notifier, HeartbeatRegistry& heartbeats);
  ~ServiceWatchdog();  // stops and joins
  ServiceWatchdog(const ServiceWatchdog&) = delete;
  ServiceWatchdog& operator=(const ServiceWatchdog&) = delete;

  // How old a heartbeat may be for a given WatchdogSec: the interval itself, at least 2 s
  // (a loaded board takes a few hundred ms for a frame now and then; the unit's 5 s gives 5 s).
  static std::chrono::milliseconds stale_after(SystemdNotifier& notifier);

 private:
  void run(std::stop_token stop);

  SystemdNotifier& notifier_;
  HeartbeatRegistry& heartbeats_;
  std::jthread thread_;
};

}  // namespace probeless
