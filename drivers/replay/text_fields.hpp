#pragma once
// Fields of the line-based files of recordings and TUM sequences. Numbers are written in the
// shortest form that reads back to the same value (std::to_chars) and read with
// std::from_chars, so a double survives a write/read cycle bit for bit. Every parse failure
// is a ParseError naming the file and the 1-based line.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/time.hpp"

namespace probeless::replay {

// Where a field came from, for error messages.
struct TextLocation {
  std::string source;  // file name as the user knows it
  int line = 0;        // 1-based
  [[noreturn]] void fail(const std::string& what) const { throw ParseError(source, line, what); }
};

std::string format_double(double value);  // shortest round-trip form
double parse_double(std::string_view text, const TextLocation& where, std::string_view what);
std::int64_t parse_int64(std::string_view text, const TextLocation& where, std::string_view what);
std::uint64_t parse_uint64(std::string_view text, const TextLocation& where, std::string_view what);
// Within [lo, hi]; otherwise a ParseError naming `what` and the range.
std::int64_t parse_int_in(std::string_view text, std::int64_t lo, std::int64_t hi,
                          const TextLocation& where, std::string_view what);

// Seconds with nine decimals, exactly the nanoseconds given ("12.000000345").
std::string format_seconds(TimestampNs ns);
// Decimal seconds -> nanoseconds without going through a double (TUM's "1305031102.175304"
// is exact); digits beyond the ninth decimal are rounded.
TimestampNs parse_seconds(std::string_view text, const TextLocation& where);

// Splits on `separator` (every occurrence; empty fields kept).
std::vector<std::string_view> split_fields(std::string_view line, char separator);
// Splits on runs of spaces and tabs (TUM's text files).
std::vector<std::string_view> split_whitespace(std::string_view line);

// A whole text file as lines (without "\n" or a trailing "\r"). Throws ParseError (line 0)
// when the file cannot be read. `complete_lines_only`: a last line without its "\n" (a
// write cut short by a crash) is left out.
std::vector<std::string> read_text_lines(const std::filesystem::path& path,
                                         bool complete_lines_only = false);

}  // namespace probeless::replay
