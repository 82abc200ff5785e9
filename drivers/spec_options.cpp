#include "drivers/spec_options.hpp"

#include <algorithm>
#include <stdexcept>

namespace probeless {

std::pair<std::string_view, std::string_view> split_spec(std::string_view spec) {
  const std::size_t q = spec.rfind('?');
  if (q == std::string_view::npos) return {spec, {}};
  return {spec.substr(0, q), spec.substr(q + 1)};
}

std::vector<SpecOption> spec_options(std::string_view options) {
  std::vector<SpecOption> out;
  std::size_t pos = 0;
  while (pos < options.size()) {
    const std::size_t end = std::min(options.find_first_of(",&", pos), options.size());
    const std::string_view item = options.substr(pos, end - pos);
    pos = end + 1;
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    out.push_back({item.substr(0, eq),
                   eq == std::string_view::npos ? std::string_view() : item.substr(eq + 1)});
  }
  return out;
}

void bad_spec_option(std::string_view source, std::string_view key, std::string_view value,
                     std::string_view expected) {
  throw std::invalid_argument(std::string(source) + " option '" + std::string(key) +
                              "': expected " + std::string(expected) + ", got '" +
                              std::string(value) + "'");
}

bool spec_flag(std::string_view source, std::string_view key, std::string_view value) {
  if (value == "1") return true;
  if (value == "0") return false;
  bad_spec_option(source, key, value, "0 or 1");
}

}  // namespace probeless
