#include "drivers/openni2/openni2_options.hpp"

#include <charconv>
#include <stdexcept>

#include "drivers/usb/usb_hotplug.hpp"

namespace probeless::openni2 {
namespace {

[[noreturn]] void bad(std::string_view key, std::string_view value, std::string_view expected) {
  throw std::invalid_argument("openni2 option '" + std::string(key) + "': expected " +
                              std::string(expected) + ", got '" + std::string(value) + "'");
}

template <typename T>
T number(std::string_view key, std::string_view value, T lo, T hi, std::string_view expected) {
  T out{};
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), out);
  if (ec != std::errc() || end != value.data() + value.size() || out < lo || out > hi)
    bad(key, value, expected);
  return out;
}

bool flag(std::string_view key, std::string_view value) {
  if (value == "1") return true;
  if (value == "0") return false;
  bad(key, value, "0 or 1");
}

}  // namespace

Openni2Options parse_openni2_options(std::string_view spec) {
  Openni2Options o;
  o.usb_vendors = usb::default_sensor_vendors();
  // The options follow the last '?', as for v4l2: and replay: (URIs and paths have none).
  const std::size_t q = spec.rfind('?');
  o.uri = std::string(spec.substr(0, q));
  const std::string_view opts = q == std::string_view::npos ? "" : spec.substr(q + 1);
  bool file_option = false;
  std::size_t pos = 0;
  while (pos < opts.size()) {
    const std::size_t end = std::min(opts.find_first_of(",&", pos), opts.size());
    const std::string_view item = opts.substr(pos, end - pos);
    pos = end + 1;
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    const std::string_view key = item.substr(0, eq);
    const std::string_view value = eq == std::string_view::npos ? "" : item.substr(eq + 1);
    if (key == "size") {
      const std::size_t x = value.find('x');
      if (x == std::string_view::npos) bad(key, value, "WIDTHxHEIGHT");
      o.width = number<int>(key, value.substr(0, x), 16, 4096, "WIDTHxHEIGHT");
      o.height = number<int>(key, value.substr(x + 1), 16, 4096, "WIDTHxHEIGHT");
    } else if (key == "fps") {
      o.fps = number<int>(key, value, 1, 1000, "a whole frame rate in 1..1000");
    } else if (key == "registration") {
      o.registration = flag(key, value);
    } else if (key == "sync") {
      o.sync = flag(key, value);
    } else if (key == "pair_ms") {
      o.pair_ms = number<int>(key, value, 0, 1000, "0..1000");
    } else if (key == "reopen_ms") {
      o.reopen_ms = number<int>(key, value, 10, 60000, "10..60000");
    } else if (key == "stall_ms") {
      o.stall_ms = number<int>(key, value, 100, 60000, "100..60000");
    } else if (key == "reset_on_stall") {
      o.reset_on_stall = flag(key, value);
    } else if (key == "hotplug") {
      o.hotplug = flag(key, value);
    } else if (key == "usb_vendors") {
      o.usb_vendors = usb::parse_vendor_list(value);
    } else if (key == "speed") {
      o.speed = number<double>(key, value, 0.0, 100.0, "a playback speed in [0, 100] (0: fastest)");
      file_option = true;
    } else if (key == "repeat") {
      o.repeat = flag(key, value);
      file_option = true;
    } else {
      throw std::invalid_argument("openni2: unknown option '" + std::string(key) +
                                  "' (known: size, fps, registration, sync, pair_ms, reopen_ms, "
                                  "stall_ms, reset_on_stall, hotplug, usb_vendors, speed, "
                                  "repeat)");
    }
  }
  if (file_option && !o.is_file()) {
    throw std::invalid_argument(
        "openni2: speed and repeat are for recordings (a URI ending in "
        "'.oni'), not for the device '" +
        o.uri + "'");
  }
  return o;
}

}  // namespace probeless::openni2
