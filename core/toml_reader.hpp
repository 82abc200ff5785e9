#pragma once
// Typed access to a toml++ tree for every TOML the project reads (rig calibration, service
// config): each problem becomes a ParseError naming the source and the line of the offending
// node, or of the table a key is missing from, so the CLI prints it as it is.
#include <toml++/toml.h>

#include <Eigen/Core>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace probeless {

class TomlReader {
 public:
  explicit TomlReader(std::string source) : source_(std::move(source)) {}

  // Parses `text`; a syntax error is a ParseError at its line.
  toml::table parse(std::string_view text) const;

  [[noreturn]] void fail(const toml::node* node, const std::string& what) const;

  // Rejects keys this version does not know, naming the first one.
  void only(const toml::table& table, std::string_view where,
            std::initializer_list<std::string_view> known) const;

  // Required members: a missing key fails at the table's line.
  const toml::node& require(const toml::table& table, std::string_view where,
                            std::string_view key) const;
  const toml::table& table(const toml::table& parent, std::string_view where,
                           std::string_view key) const;
  double number(const toml::table& t, std::string_view where, std::string_view key) const {
    return number(require(t, where, key), key);
  }
  // An image's or a camera's "width" and "height" within core/read_limits.hpp, so that what
  // is sized from them (maps, buffers) cannot be absurd.
  std::pair<int, int> image_size(const toml::table& t, std::string_view where) const;
  std::vector<double> numbers(const toml::table& t, std::string_view where, std::string_view key,
                              std::size_t min, std::size_t max) const {
    return numbers(require(t, where, key), key, min, max);
  }
  std::string string(const toml::table& t, std::string_view where, std::string_view key) const;

  // Optional members: absent leaves the default.
  const toml::table* optional_table(const toml::table& parent, std::string_view key) const;
  double number_or(const toml::table& t, std::string_view key, double fallback) const {
    const toml::node* node = t.get(key);
    return node ? number(*node, key) : fallback;
  }
  template <typename T>
  void get(const toml::table& table, std::string_view key, T& out) const;
  template <int N, typename Scalar>
  void get_vector(const toml::table& table, std::string_view key,
                  Eigen::Matrix<Scalar, N, 1>& out) const;

  // Values: integers are accepted as numbers; NaN and infinity are not.
  double number(const toml::node& node, std::string_view key) const;
  std::vector<double> numbers(const toml::node& node, std::string_view key, std::size_t min,
                              std::size_t max) const;

 private:
  std::string source_;
};

template <typename T>
void TomlReader::get(const toml::table& table, std::string_view key, T& out) const {
  const toml::node* node = table.get(key);
  if (!node) return;
  if constexpr (std::is_same_v<T, bool>) {
    if (!node->is_boolean()) fail(node, std::string(key) + ": expected true or false");
    out = node->as_boolean()->get();
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!node->is_string()) fail(node, std::string(key) + ": expected a string");
    out = node->as_string()->get();
  } else if constexpr (std::is_integral_v<T>) {
    if (!node->is_integer()) fail(node, std::string(key) + ": expected an integer");
    // TOML integers are 64-bit: one that does not fit T is an error, not its low bits (a port
    // of 4294975616 would bind 8320).
    const std::int64_t v = node->as_integer()->get();
    if (!std::in_range<T>(v))
      fail(node, std::string(key) + ": " + std::to_string(v) + " is out of range (" +
                     std::to_string(std::numeric_limits<T>::min()) + ".." +
                     std::to_string(std::numeric_limits<T>::max()) + ")");
    out = static_cast<T>(v);
  } else {
    out = static_cast<T>(number(*node, key));
  }
}

template <int N, typename Scalar>
void TomlReader::get_vector(const toml::table& table, std::string_view key,
                            Eigen::Matrix<Scalar, N, 1>& out) const {
  const toml::node* node = table.get(key);
  if (!node) return;
  const std::vector<double> v = numbers(*node, key, N, N);
  for (int i = 0; i < N; ++i) out[i] = static_cast<Scalar>(v[static_cast<std::size_t>(i)]);
}

}  // namespace probeless
