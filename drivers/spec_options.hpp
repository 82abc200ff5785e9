#pragma once
// The "BASE?key=value,key=value" option syntax the device sources share (`v4l2:`,
// `openni2:`; docs/drivers.md): split at the last '?' (URIs, paths and card names have none),
// items separated by ',' or '&', and errors that name the source, the key and what was
// expected.
#include <charconv>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace probeless {

struct SpecOption {
  std::string_view key, value;  // value is empty for an item without '='
};

// {BASE, OPTIONS}; OPTIONS is empty without a '?'.
std::pair<std::string_view, std::string_view> split_spec(std::string_view spec);
// The items of OPTIONS in order; empty items are skipped.
std::vector<SpecOption> spec_options(std::string_view options);

// Throws std::invalid_argument "<source> option '<key>': expected <expected>, got '<value>'".
[[noreturn]] void bad_spec_option(std::string_view source, std::string_view key,
                                  std::string_view value, std::string_view expected);

// The whole of `value` as a number in [lo, hi], else bad_spec_option.
template <typename T>
T spec_number(std::string_view source, std::string_view key, std::string_view value, T lo, T hi,
              std::string_view expected) {
  T out{};
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), out);
  if (ec != std::errc() || end != value.data() + value.size() || out < lo || out > hi)
    bad_spec_option(source, key, value, expected);
  return out;
}

// "1" or "0", else bad_spec_option.
bool spec_flag(std::string_view source, std::string_view key, std::string_view value);

}  // namespace probeless
