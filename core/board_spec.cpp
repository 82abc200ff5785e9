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

// Their marker counts, in the same order (the apriltag ones as OpenCV 4.6 ships them).
constexpr std::array<int, 21> kDictionarySizes{50,   100,  250,  1000, 50,   100,  250,
                                               1000, 50,   100,  250,  1000, 50,   100,
                                               250,  1000, 1024, 30,   35,   2320, 587};

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
                              "charuco:5x7:40:20:6x6_250, chessboard:COLSxROWS:SQUARE_MM or "
                              "aruco:ID:SIDE_MM:DICT, e.g. aruco:0:150:4x4_50)");
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

std::string parse_dictionary(std::string_view spec, std::string_view text) {
  std::string dict(text);
  std::transform(dict.begin(), dict.end(), dict.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (dict.starts_with("dict_")) dict.erase(0, 5);
  if (board_dictionary_index(dict) < 0)
    bad(spec, "dictionary '" + std::string(text) + "' is not one of " + board_dictionaries());
  return dict;
}

BoardSpec parse_aruco(std::string_view spec, const std::vector<std::string_view>& parts) {
  if (parts.size() != 4) bad(spec, "an ArUco marker has three fields after 'aruco:'");
  BoardSpec b;
  b.kind = BoardSpec::Kind::Aruco;
  b.dictionary = parse_dictionary(spec, parts[3]);
  const int size = board_dictionary_size(b.dictionary);
  const auto [end, ec] =
      std::from_chars(parts[1].data(), parts[1].data() + parts[1].size(), b.marker_id);
  if (ec != std::errc{} || end != parts[1].data() + parts[1].size() || b.marker_id < 0 ||
      b.marker_id >= size)
    bad(spec, "marker id '" + std::string(parts[1]) + "' is not in 0.." + std::to_string(size - 1) +
                  " (the dictionary's markers)");
  b.marker_mm = parse_mm(spec, parts[2], "marker side");
  return b;
}

}  // namespace

BoardSpec parse_board_spec(std::string_view spec) {
  std::vector<std::string_view> parts = split(spec, ':');
  if (parts.front() == "aruco") return parse_aruco(spec, parts);
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
  b.dictionary = parse_dictionary(spec, parts[3]);
  return b;
}

int board_dictionary_index(std::string_view name) {
  const auto it = std::find(kDictionaries.begin(), kDictionaries.end(), name);
  return it == kDictionaries.end() ? -1 : static_cast<int>(it - kDictionaries.begin());
}

int board_dictionary_size(std::string_view name) {
  const int i = board_dictionary_index(name);
  return i < 0 ? 0 : kDictionarySizes[static_cast<std::size_t>(i)];
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
