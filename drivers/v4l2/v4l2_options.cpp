#include "drivers/v4l2/v4l2_options.hpp"

#include <charconv>
#include <stdexcept>

namespace probeless::v4l2 {
namespace {

[[noreturn]] void bad(std::string_view key, std::string_view value, std::string_view expected) {
  throw std::invalid_argument("v4l2 option '" + std::string(key) + "': expected " +
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

}  // namespace

V4l2Options parse_v4l2_options(std::string_view spec) {
  V4l2Options o;
  // The options follow the last '?', as for replay: and tum: (a device path has none).
  const std::size_t q = spec.rfind('?');
  o.device = std::string(spec.substr(0, q));
  if (o.device.empty())
    throw std::invalid_argument("source 'v4l2:' needs a device (v4l2:/dev/video0 or v4l2:CARD)");
  const std::string_view opts = q == std::string_view::npos ? "" : spec.substr(q + 1);
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
