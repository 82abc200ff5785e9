#include "core/board_spec.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace probeless {
namespace {

TEST(BoardSpec, ChArUcoWithAndWithoutItsPrefix) {
  for (const char* text : {"charuco:5x7:40:20:6x6_250", "5x7:40:20:DICT_6X6_250"}) {
    const BoardSpec b = parse_board_spec(text);
    EXPECT_EQ(b.kind, BoardSpec::Kind::Charuco) << text;
    EXPECT_EQ(b.cols, 5);
    EXPECT_EQ(b.rows, 7);
    EXPECT_DOUBLE_EQ(b.square_mm, 40);
    EXPECT_DOUBLE_EQ(b.marker_mm, 20);
    EXPECT_EQ(b.dictionary, "6x6_250");
  }
}

TEST(BoardSpec, Chessboard) {
  const BoardSpec b = parse_board_spec("chessboard:9x6:24.5");
  EXPECT_EQ(b.kind, BoardSpec::Kind::Chessboard);
  EXPECT_EQ(b.cols, 9);
  EXPECT_EQ(b.rows, 6);
  EXPECT_DOUBLE_EQ(b.square_mm, 24.5);
}

TEST(BoardSpec, ASingleArucoMarker) {
  const BoardSpec b = parse_board_spec("aruco:23:150:DICT_4X4_50");
  EXPECT_EQ(b.kind, BoardSpec::Kind::Aruco);
  EXPECT_EQ(b.marker_id, 23);
  EXPECT_DOUBLE_EQ(b.marker_mm, 150);
  EXPECT_EQ(b.dictionary, "4x4_50");
  EXPECT_EQ(board_dictionary_size("4x4_50"), 50);
  EXPECT_EQ(board_dictionary_size("apriltag_36h11"), 587);
  EXPECT_EQ(board_dictionary_size("nope"), 0);
}

TEST(BoardSpec, DictionaryIndexIsOpenCvsEnumValue) {
  EXPECT_EQ(board_dictionary_index("4x4_50"), 0);    // cv::aruco::DICT_4X4_50
  EXPECT_EQ(board_dictionary_index("6x6_250"), 10);  // cv::aruco::DICT_6X6_250
  EXPECT_EQ(board_dictionary_index("apriltag_36h11"), 20);
  EXPECT_EQ(board_dictionary_index("6x6_251"), -1);
}

TEST(BoardSpec, BadSpecsAreClearErrors) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "four fields"},
      {"charuco:5x7:40:20", "four fields"},
      {"5by7:40:20:6x6_250", "COLSxROWS"},
      {"1x7:40:20:6x6_250", "columns"},
      {"5x7:0:20:6x6_250", "square side"},
      {"5x7:40:-2:6x6_250", "marker side"},
      {"5x7:40:40:6x6_250", "smaller than its square"},
      {"5x7:40:20:6x6_999", "is not one of"},
      {"chessboard:9x6", "two fields"},
      {"chessboard:9x6:abc", "square side"},
      {"aruco:3:100", "three fields"},
      {"aruco:50:100:4x4_50", "0..49"},
      {"aruco:-1:100:4x4_50", "marker id"},
      {"aruco:x:100:4x4_50", "marker id"},
      {"aruco:3:0:4x4_50", "marker side"},
      {"aruco:3:100:9x9_50", "is not one of"},
  };
  for (const auto& [text, why] : cases) {
    try {
      parse_board_spec(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << text << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("expected charuco:"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace probeless
