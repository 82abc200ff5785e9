#pragma once
// The systemd notify protocol (sd_notify(3)) as the service uses it: READY=1 once sources
// are open and the first frame is out, STATUS= with the frame rate, WATCHDOG=1 from the
// processing loop, STOPPING=1 at shutdown. Without NOTIFY_SOCKET (run from a shell, in
// tests) every call is a no-op, so the service code never asks whether systemd is there.
#include <chrono>
#include <optional>
#include <string_view>

namespace probeless {

class SystemdNotifier {
 public:
  // Reads NOTIFY_SOCKET and WATCHDOG_USEC (with WATCHDOG_PID) from the environment.
  SystemdNotifier();

  bool enabled() const { return enabled_; }  // NOTIFY_SOCKET is set

  // Each returns what sd_notify returned: > 0 sent, 0 no socket, < 0 -errno. The service
  // logs a failure; it never stops for one.
  int ready();
  int status(std::string_view text);  // one line: newlines become spaces
  int watchdog();
  int stopping();
  int notify(std::string_view assignments);  // raw "KEY=value\nKEY=value"

  // WATCHDOG_USEC when the unit has WatchdogSec= set (and the watchdog is meant for this
  // process); ping at half of it, as sd_watchdog_enabled(3) advises.
  std::optional<std::chrono::microseconds> watchdog_interval() const { return watchdog_; }

 private:
  bool enabled_ = false;
  std::optional<std::chrono::microseconds> watchdog_;
};

}  // namespace probeless
