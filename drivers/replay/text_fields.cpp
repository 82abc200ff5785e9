#include "drivers/replay/text_fields.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

namespace probeless::replay {
namespace {

std::string quoted(std::string_view text) {
  std::string out = "'";
  out.append(text.substr(0, 64));
  if (text.size() > 64) out += "...";
  return out + "'";
}

template <typename T>
T parse_integer(std::string_view text, const TextLocation& where, std::string_view what) {
  T value{};
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec == std::errc::invalid_argument || ptr != end) {
    where.fail("bad " + std::string(what) + " " + quoted(text) + " (expected an integer)");
  }
  if (ec == std::errc::result_out_of_range) {
    where.fail(std::string(what) + " " + quoted(text) + " is out of range");
  }
  return value;
}

}  // namespace

std::string format_double(double value) {
  std::array<char, 32> buffer{};
  const auto [ptr, ec] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  (void)ec;  // 32 characters always suffice for the shortest form of a double
  return std::string(buffer.data(), ptr);
}

double parse_double(std::string_view text, const TextLocation& where, std::string_view what) {
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc{} || ptr != end || !std::isfinite(value)) {
    where.fail("bad " + std::string(what) + " " + quoted(text) + " (expected a finite number)");
  }
  return value;
}

std::int64_t parse_int64(std::string_view text, const TextLocation& where, std::string_view what) {
  return parse_integer<std::int64_t>(text, where, what);
}

std::uint64_t parse_uint64(std::string_view text, const TextLocation& where,
                           std::string_view what) {
  return parse_integer<std::uint64_t>(text, where, what);
}

std::int64_t parse_int_in(std::string_view text, std::int64_t lo, std::int64_t hi,
                          const TextLocation& where, std::string_view what) {
  const std::int64_t v = parse_int64(text, where, what);
  if (v < lo || v > hi) {
    where.fail(std::string(what) + " " + std::to_string(v) + " is outside [" + std::to_string(lo) +
               ", " + std::to_string(hi) + "]");
  }
  return v;
}

std::string format_seconds(TimestampNs ns) {
  const bool negative = ns < 0;
  // Work in unsigned magnitude so that INT64_MIN does not overflow.
  const std::uint64_t magnitude =
      negative ? std::uint64_t{0} - static_cast<std::uint64_t>(ns) : static_cast<std::uint64_t>(ns);
  char text[32];
  const int n = std::snprintf(text, sizeof text, "%s%llu.%09llu", negative ? "-" : "",
                              static_cast<unsigned long long>(magnitude / 1'000'000'000u),
                              static_cast<unsigned long long>(magnitude % 1'000'000'000u));
  return std::string(text, static_cast<std::size_t>(n));
}

TimestampNs parse_seconds(std::string_view text, const TextLocation& where) {
  const auto bad = [&] {
    where.fail("bad timestamp " + quoted(text) + " (expected seconds such as 1305031102.175304)");
  };
  std::string_view rest = text;
  const bool negative = !rest.empty() && rest.front() == '-';
  if (negative) rest.remove_prefix(1);
  const std::size_t dot = rest.find('.');
  const std::string_view whole = rest.substr(0, dot);
  std::string_view decimals =
      dot == std::string_view::npos ? std::string_view{} : rest.substr(dot + 1);
  if (whole.empty() && decimals.empty()) bad();
  for (char c : whole)
    if (c < '0' || c > '9') bad();
  for (char c : decimals)
    if (c < '0' || c > '9') bad();

  constexpr std::uint64_t kMaxSeconds =
      std::numeric_limits<std::int64_t>::max() / 1'000'000'000 - 1;
  std::uint64_t seconds = 0;
  if (!whole.empty()) {
    const auto [ptr, ec] = std::from_chars(whole.data(), whole.data() + whole.size(), seconds);
    (void)ptr;
    if (ec != std::errc{} || seconds > kMaxSeconds)
      where.fail("timestamp " + quoted(text) + " is out of range");
  }
  std::uint64_t nanos = 0;
  for (std::size_t i = 0; i < 9; ++i) {
    nanos = nanos * 10 + (i < decimals.size() ? static_cast<std::uint64_t>(decimals[i] - '0') : 0);
  }
  if (decimals.size() > 9 && decimals[9] >= '5') ++nanos;  // round half up on the tenth digit
  const auto total = static_cast<std::int64_t>(seconds * 1'000'000'000u + nanos);
  return negative ? -total : total;
}

std::vector<std::string_view> split_fields(std::string_view line, char separator) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t pos = line.find(separator, start);
    if (pos == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return fields;
    }
    fields.push_back(line.substr(start, pos - start));
    start = pos + 1;
  }
}

std::vector<std::string_view> split_whitespace(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

std::vector<std::string> read_text_lines(const std::filesystem::path& path,
                                         bool complete_lines_only) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ParseError(path.string(), 0, "cannot open for reading");
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (in.eof() && complete_lines_only) break;  // no "\n" after it
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
  }
  if (in.bad()) throw ParseError(path.string(), 0, "read error");
  return lines;
}

}  // namespace probeless::replay
