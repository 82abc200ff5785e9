#include "drivers/openni2/openni2_options.hpp"

#include <stdexcept>

#include "drivers/spec_options.hpp"
#include "drivers/usb/usb_hotplug.hpp"

namespace probeless::openni2 {
namespace {

constexpr std::string_view kSource = "openni2";

[[noreturn]] void bad(std::string_view key, std::string_view value, std::string_view expected) {
  bad_spec_option(kSource, key, value, expected);
}

template <typename T>
T number(std::string_view key, std::string_view value, T lo, T hi, std::string_view expected) {
  return spec_number(kSource, key, value, lo, hi, expected);
}

bool flag(std::string_view key, std::string_view value) {
  return spec_flag(kSource, key, value);
}

}  // namespace

Openni2Options parse_openni2_options(std::string_view spec) {
  Openni2Options o;
  o.usb_vendors = usb::default_sensor_vendors();
  // The options follow the last '?', as for v4l2: and replay: (URIs and paths have none).
  const auto [base, opts] = split_spec(spec);
  o.uri = std::string(base);
  bool file_option = false;
  for (const auto& [key, value] : spec_options(opts)) {
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
