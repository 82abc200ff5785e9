// The appliance's marker detector (app/world/board_detector) on OpenCV's own tutorial photos
// (../shared/data/aruco): the lone-marker path here, the ChArUco path through `eval marker`'s
// tests (tests/unit/eval/marker_eval_test.cpp), which call the same detector.
#include "app/world/board_detector.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iostream>
#include <iterator>
#include <vector>

#include "app/outputs/jpeg_encoder.hpp"
#include "lab/eval/marker_eval.hpp"
#include "support/test_data.hpp"

namespace probeless::world {
namespace {

ImageRGB8 read_jpeg(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
  return JpegDecoder().decode(bytes);
}

TEST(BoardDetector, FindsTheTutorialsSingleMarkersWithSubPixelCorners) {
  PROBELESS_REQUIRE_DATA("aruco/singlemarkersoriginal.jpg");
  const auto dir = testing::shared_data_dir() / "aruco";
  const BoardCamera camera = eval::read_opencv_camera(dir / "tutorial_camera_params.yml");
  const ImageRGB8 photo = read_jpeg(dir / "singlemarkersoriginal.jpg");
  int found = 0;
  for (int id = 0; id < 250; ++id) {
    BoardSpec spec = parse_board_spec("aruco:0:50:6x6_250");
    spec.marker_id = id;
    const BoardDetection d = BoardDetector(spec, camera).detect(photo);
    if (!d.found) continue;
    ++found;
    EXPECT_EQ(d.corners, 4);
    EXPECT_LT(d.rms_px, 1.0) << "id " << id;
    EXPECT_GT(d.T_camera_board.translation.z(), 0.05) << "in front of the camera, id " << id;
    // z out of the printed face: towards the camera, which looks along +z.
    EXPECT_LT((d.T_camera_board.rotation * Eigen::Vector3d::UnitZ()).z(), 0) << "id " << id;
  }
  std::cout << "singlemarkersoriginal.jpg: " << found << " markers of 6x6_250 found\n";
  EXPECT_GE(found, 5) << "the photo shows a page of markers";
  EXPECT_FALSE(BoardDetector(parse_board_spec("aruco:0:50:4x4_50"), camera).detect(photo).found);
}

TEST(BoardDetector, BadInputsAreClearErrors) {
  BoardCamera camera;
  camera.K = {500, 0, 320, 0, 500, 240, 0, 0, 1};
  camera.width = 640;
  camera.height = 480;
  EXPECT_THROW(BoardDetector(parse_board_spec("chessboard:9x6:25"), camera), std::invalid_argument);
  BoardCamera bad = camera;
  bad.K[0] = 0;
  EXPECT_THROW(BoardDetector(parse_board_spec("aruco:1:50:4x4_50"), bad), std::invalid_argument);
  const BoardDetector d(parse_board_spec("charuco:5x4:80:60:4x4_50"), camera);
  EXPECT_THROW(d.detect(ImageRGB8(320, 240)), std::invalid_argument);
  EXPECT_FALSE(d.detect(ImageRGB8(640, 480)).found);
}

}  // namespace
}  // namespace probeless::world
