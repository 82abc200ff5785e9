#include "drivers/libcamera/libcamera_options.hpp"

#include <stdexcept>

#include "drivers/spec_options.hpp"

namespace probeless::libcam {
namespace {

constexpr std::string_view kSource = "libcamera";

template <typename T>
T number(std::string_view key, std::string_view value, T lo, T hi, std::string_view expected) {
  return spec_number(kSource, key, value, lo, hi, expected);
}

}  // namespace

LibcameraOptions parse_libcamera_options(std::string_view spec) {
  LibcameraOptions o;
  // Camera ids hold '/', ' ' and ':' but no '?': the options follow the last '?'.
  const auto [base, opts] = split_spec(spec);
  o.camera_id = std::string(base);
  for (const auto& [key, value] : spec_options(opts)) {
    if (key == "size") {
      const std::size_t x = value.find('x');
      if (x == std::string_view::npos) bad_spec_option(kSource, key, value, "WIDTHxHEIGHT");
      o.width = number<int>(key, value.substr(0, x), 16, 8192, "WIDTHxHEIGHT");
      o.height = number<int>(key, value.substr(x + 1), 16, 8192, "WIDTHxHEIGHT");
    } else if (key == "format") {
      if (value.empty() || value.size() > 16)
        bad_spec_option(kSource, key, value,
                        "a libcamera format name (SRGGB12, BGR888, YUYV, ...)");
      o.format = std::string(value);
    } else if (key == "buffers") {
      o.buffers = number<int>(key, value, 2, 32, "2..32");
    } else if (key == "reopen_ms") {
      o.reopen_ms = number<int>(key, value, 10, 60000, "10..60000");
    } else if (key == "stall_ms") {
      o.stall_ms = number<int>(key, value, 50, 60000, "50..60000");
    } else {
      throw std::invalid_argument("libcamera: unknown option '" + std::string(key) +
                                  "' (known: size, format, buffers, reopen_ms, stall_ms)");
    }
  }
  return o;
}

}  // namespace probeless::libcam
