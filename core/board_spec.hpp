#pragma once
// A calibration or anchoring target named in one string (issues #17, #18; docs/tracking.md
// "Boards"): `charuco:COLSxROWS:SQUARE_MM:MARKER_MM:DICT` (the `charuco:` may be left out) or
// `chessboard:COLSxROWS:SQUARE_MM` (inner corners) or a single ArUco marker
// `aruco:ID:SIDE_MM:DICT` (world anchoring, docs/tracking.md "World anchoring"). COLS x ROWS of a
// ChArUco board count its squares, as OpenCV's CharucoBoard::create(squaresX, squaresY, ...) does;
// DICT is an OpenCV predefined dictionary without its prefix, e.g. `6x6_250` for DICT_6X6_250.
// Example: `5x7:40:20:6x6_250`, the board of OpenCV's ChArUco tutorial.
#include <string>
#include <string_view>

namespace probeless {

struct BoardSpec {
  enum class Kind { Charuco, Chessboard, Aruco };
  Kind kind = Kind::Charuco;
  int cols = 0, rows = 0;  // squares (ChArUco) or inner corners (chessboard)
  double square_mm = 0;    // side of a chessboard square
  double marker_mm = 0;    // side of an ArUco marker (inside a white square on ChArUco)
  std::string dictionary;  // lower case, e.g. "6x6_250" (ChArUco, ArUco)
  int marker_id = 0;       // the marker's id in its dictionary (ArUco)
};

// Throws std::invalid_argument naming the part that is wrong and the expected form.
BoardSpec parse_board_spec(std::string_view spec);

// The dictionaries parse_board_spec accepts, comma-separated, for messages and help texts.
std::string board_dictionaries();

// A dictionary's position in that list, which is OpenCV's PREDEFINED_DICTIONARY_NAME value
// (DICT_4X4_50 = 0 ... DICT_APRILTAG_36h11 = 20); -1 for an unknown name.
int board_dictionary_index(std::string_view name);
// How many markers that dictionary has (OpenCV 4.6's sizes); 0 for an unknown name.
int board_dictionary_size(std::string_view name);

}  // namespace probeless
