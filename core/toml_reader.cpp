#include "core/toml_reader.hpp"

#include <cmath>
#include <set>

#include "core/read_limits.hpp"

namespace probeless {

toml::table TomlReader::parse(std::string_view text) const {
  try {
    return toml::parse(text, source_);
  } catch (const toml::parse_error& e) {
    throw ParseError(source_, static_cast<int>(e.source().begin.line),
                     std::string(e.description()));
  }
}

void TomlReader::fail(const toml::node* node, const std::string& what) const {
  // A node parsed from another file (a board file merged under a config) names that file.
  const auto& from = node ? node->source().path : nullptr;
  throw ParseError(from ? *from : source_, node ? static_cast<int>(node->source().begin.line) : 0,
                   what);
}

void TomlReader::only(const toml::table& table, std::string_view where,
                      std::initializer_list<std::string_view> known) const {
  const std::set<std::string_view> allowed(known);
  for (const auto& [key, node] : table) {
    if (!allowed.contains(key.str())) {
      std::string what = "unknown key '";
      what.append(key.str()).append("' in ").append(where);
      fail(&node, what);
    }
  }
}

const toml::node& TomlReader::require(const toml::table& table, std::string_view where,
                                      std::string_view key) const {
  const toml::node* node = table.get(key);
  if (!node) {
    std::string what = "missing key '";
    what.append(key).append("' in ").append(where);
    fail(&table, what);
  }
  return *node;
}

const toml::table& TomlReader::table(const toml::table& parent, std::string_view where,
                                     std::string_view key) const {
  const toml::node& node = require(parent, where, key);
  if (!node.is_table()) fail(&node, std::string(key) + ": expected a table");
  return *node.as_table();
}

const toml::table* TomlReader::optional_table(const toml::table& parent,
                                              std::string_view key) const {
  const toml::node* node = parent.get(key);
  if (!node) return nullptr;
  if (!node->is_table()) {
    std::string what(key);
    what.append(": expected a table [").append(key).append("]");
    fail(node, what);
  }
  return node->as_table();
}

double TomlReader::number(const toml::node& node, std::string_view key) const {
  const auto v = node.value<double>();
  if (!v || !std::isfinite(*v)) fail(&node, std::string(key) + ": expected a number");
  return *v;
}

std::pair<int, int> TomlReader::image_size(const toml::table& t, std::string_view where) const {
  std::int64_t size[2] = {};
  const char* keys[2] = {"width", "height"};
  for (int i = 0; i < 2; ++i) {
    const toml::node& node = require(t, where, keys[i]);
    const auto v = node.value_exact<std::int64_t>();
    if (!v || *v <= 0 || *v > read_limits::kMaxImageSide)
      fail(&node, std::string(keys[i]) + ": expected a positive integer up to " +
                      std::to_string(read_limits::kMaxImageSide));
    size[i] = *v;
  }
  if (!read_limits::image_size_ok(size[0], size[1]))
    fail(t.get("height"), std::to_string(size[0]) + "x" + std::to_string(size[1]) +
                              " is over the limit of " +
                              std::to_string(read_limits::kMaxImagePixels) + " pixels");
  return {static_cast<int>(size[0]), static_cast<int>(size[1])};
}

std::vector<double> TomlReader::numbers(const toml::node& node, std::string_view key,
                                        std::size_t min, std::size_t max) const {
  const toml::array* arr = node.as_array();
  if (!arr || arr->size() < min || arr->size() > max) {
    std::string what(key);
    what.append(": expected an array of ")
        .append(min == max ? std::to_string(min)
                           : std::to_string(min) + " to " + std::to_string(max))
        .append(" numbers");
    fail(&node, what);
  }
  std::vector<double> out;
  out.reserve(arr->size());
  for (const toml::node& item : *arr) out.push_back(number(item, key));
  return out;
}

std::string TomlReader::string(const toml::table& t, std::string_view where,
                               std::string_view key) const {
  const toml::node& node = require(t, where, key);
  if (!node.is_string()) fail(&node, std::string(key) + ": expected a string");
  return node.as_string()->get();
}

}  // namespace probeless
