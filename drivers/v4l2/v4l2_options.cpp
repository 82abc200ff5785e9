#include "drivers/v4l2/v4l2_options.hpp"

#include <stdexcept>

#include "drivers/spec_options.hpp"

namespace probeless::v4l2 {
namespace {

constexpr std::string_view kSource = "v4l2";

[[noreturn]] void bad(std::string_view key, std::string_view value, std::string_view expected) {
  bad_spec_option(kSource, key, value, expected);
}

template <typename T>
T number(std::string_view key, std::string_view value, T lo, T hi, std::string_view expected) {
  return spec_number(kSource, key, value, lo, hi, expected);
}

}  // namespace

V4l2Options parse_v4l2_options(std::string_view spec) {
  V4l2Options o;
  // The options follow the last '?', as for replay: and tum: (a device path has none).
  const auto [base, opts] = split_spec(spec);
  o.device = std::string(base);
  if (o.device.empty())
    throw std::invalid_argument("source 'v4l2:' needs a device (v4l2:/dev/video0 or v4l2:CARD)");
  for (const auto& [key, value] : spec_options(opts)) {
    if (key == "size") {
      const std::size_t x = value.find('x');
      if (x == std::string_view::npos) bad(key, value, "WIDTHxHEIGHT");
      o.width = number<int>(key, value.substr(0, x), 16, 8192, "WIDTHxHEIGHT");
      o.height = number<int>(key, value.substr(x + 1), 16, 8192, "WIDTHxHEIGHT");
    } else if (key == "fps") {
      o.fps = number<double>(key, value, 0.1, 1000.0, "a frame rate in (0, 1000]");
    } else if (key == "format") {
      if (value.size() != 4) bad(key, value, "a four-character code (YUYV, RGB3, RG12, ...)");
      o.format = std::string(value);
    } else if (key == "buffers") {
      o.buffers = number<int>(key, value, 2, 32, "2..32");
    } else if (key == "latency") {
      o.latency_frames = number<int>(key, value, 0, 8, "0..8 frames");
    } else if (key == "unity_gain") {
      o.unity_gain = number<std::int64_t>(key, value, 1, 1 << 30, "a positive raw gain");
    } else if (key == "reopen_ms") {
      o.reopen_ms = number<int>(key, value, 10, 60000, "10..60000");
    } else {
      throw std::invalid_argument("v4l2: unknown option '" + std::string(key) +
                                  "' (known: size, fps, format, buffers, latency, unity_gain, "
                                  "reopen_ms)");
    }
  }
  return o;
}

}  // namespace probeless::v4l2
