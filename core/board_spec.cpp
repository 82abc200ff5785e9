#include "core/board_spec.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <stdexcept>
#include <vector>

namespace probeless {
namespace {

// OpenCV 4.6's predefined ArUco dictionaries (opencv2/aruco/dictionary.hpp), in its order.
constexpr std::array<std::string_view, 21> kDictionaries{
    "4x4_50",        "4x4_100",        "4x4_250",       "4x4_1000",      "5x5_50",
    "5x5_100",       "5x5_250",        "5x5_1000",      "6x6_50",        "6x6_100",
    "6x6_250",       "6x6_1000",       "7x7_50",        "7x7_100",       "7x7_250",
    "7x7_1000",      "aruco_original", "apriltag_16h5", "apriltag_25h9", "apriltag_36h10",
    "apriltag_36h11"};

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= s.size(); ++i) {
    if (i == s.size() || s[i] == sep) {
      parts.push_back(s.substr(start, i - start));
      start = i + 1;
    }
  }
  return parts;
}

[[noreturn]] void bad(std::string_view spec, const std::string& why) {
  throw std::invalid_argument("board '" + std::string(spec) + "': " + why +
                              " (expected charuco:COLSxROWS:SQUARE_MM:MARKER_MM:DICT, e.g. "
                              "charuco:5x7:40:20:6x6_250, or chessboard:COLSxROWS:SQUARE_MM)");
}

int parse_count(std::string_view spec, std::string_view text, const char* what) {
  int v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc{} || end != text.data() + text.size() || v < 2 || v > 100)
    bad(spec, std::string(what) + " '" + std::string(text) + "' is not a whole number in 2..100");
  return v;
}

double parse_mm(std::string_view spec, std::string_view text, const char* what) {
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc{} || end != text.data() + text.size() || !(v > 0) || v > 10000)
    bad(spec,
        std::string(what) + " '" + std::string(text) + "' is not a length in mm in (0, 10000]");
  return v;
}

}  // namespace

BoardSpec parse_board_spec(std::string_view spec) {
  std::vector<std::string_view> parts = split(spec, ':');
  BoardSpec b;
  if (parts.front() == "chessboard") {
    b.kind = BoardSpec::Kind::Chessboard;
    parts.erase(parts.begin());
    if (parts.size() != 2) bad(spec, "a chessboard has two fields after 'chessboard:'");
  } else {
    if (parts.front() == "charuco") parts.erase(parts.begin());
    if (parts.size() != 4) bad(spec, "a ChArUco board has four fields");
  }
  const auto size = split(parts[0], 'x');
  if (size.size() != 2) bad(spec, "size '" + std::string(parts[0]) + "' is not COLSxROWS");
  b.cols = parse_count(spec, size[0], "columns");
  b.rows = parse_count(spec, size[1], "rows");
  b.square_mm = parse_mm(spec, parts[1], "square side");
  if (b.kind == BoardSpec::Kind::Chessboard) return b;
  b.marker_mm = parse_mm(spec, parts[2], "marker side");
  if (b.marker_mm >= b.square_mm) bad(spec, "the marker must be smaller than its square");
  std::string dict(parts[3]);
  std::transform(dict.begin(), dict.end(), dict.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (dict.starts_with("dict_")) dict.erase(0, 5);
  if (board_dictionary_index(dict) < 0)
    bad(spec, "dictionary '" + std::string(parts[3]) + "' is not one of " + board_dictionaries());
  b.dictionary = dict;
  return b;
}

int board_dictionary_index(std::string_view name) {
  const auto it = std::find(kDictionaries.begin(), kDictionaries.end(), name);
  return it == kDictionaries.end() ? -1 : static_cast<int>(it - kDictionaries.begin());
}

std::string board_dictionaries() {
  std::string out;
  for (auto d : kDictionaries) {
    if (!out.empty()) out += ", ";
    out += d;
  }
  return out;
}

}  // namespace probeless
