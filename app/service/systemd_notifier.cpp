#include "app/service/systemd_notifier.hpp"

#include <systemd/sd-daemon.h>

#include <cstdlib>
#include <string>

namespace probeless {

SystemdNotifier::SystemdNotifier() {
  const char* socket = std::getenv("NOTIFY_SOCKET");
  enabled_ = socket != nullptr && socket[0] != '\0';
  std::uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) {
    watchdog_ = std::chrono::microseconds(usec);
  }
}

int SystemdNotifier::notify(std::string_view assignments) {
  if (!enabled_) return 0;
  const std::string text(assignments);
  return sd_notify(0, text.c_str());
}

int SystemdNotifier::ready() {
  return notify("READY=1");
}

int SystemdNotifier::status(std::string_view text) {
  std::string line = "STATUS=";
  for (char c : text) line.push_back(c == '\n' || c == '\r' ? ' ' : c);
  return notify(line);
}

int SystemdNotifier::watchdog() {
  return notify("WATCHDOG=1");
}

int SystemdNotifier::stopping() {
  return notify("STOPPING=1");
}

}  // namespace probeless
