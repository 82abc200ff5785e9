// eval marker on OpenCV's real ChArUco photos (../shared/data/aruco, issue #17's bar:
// choriginal.jpg found, corner reprojection RMS <= 1 px).
#include "lab/eval/marker_eval.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

const BoardSpec kTutorialBoard = parse_board_spec("charuco:5x7:40:20:6x6_250");

TEST(EvalMarker, ReadsOpenCvsCameraFile) {
  PROBELESS_REQUIRE_DATA("aruco/tutorial_camera_charuco.yml");
  const auto cam =
      eval::read_opencv_camera(testing::shared_data_dir() / "aruco/tutorial_camera_charuco.yml");
  EXPECT_NEAR(cam.K[0], 452.51, 0.01);
  EXPECT_NEAR(cam.K[4], 456.77, 0.01);
  EXPECT_NEAR(cam.K[2], 317.70, 0.01);
  EXPECT_NEAR(cam.K[5], 277.75, 0.01);
  EXPECT_EQ(cam.distortion.size(), 5u);
  EXPECT_EQ(cam.width, 640);
  EXPECT_EQ(cam.height, 480);
}

TEST(EvalMarker, FindsTheBoardInTheRealPhotosWithinOnePixel) {
  PROBELESS_REQUIRE_DATA("aruco/choriginal.jpg");
  const auto dir = testing::shared_data_dir() / "aruco";
  const auto cam = eval::read_opencv_camera(dir / "tutorial_camera_charuco.yml");
  for (const char* photo : {"choriginal.jpg", "chocclusion_original.jpg"}) {
    const auto pose = eval::find_board_pose(dir / photo, cam, kTutorialBoard);
    ASSERT_TRUE(pose.found) << photo;
    EXPECT_EQ(pose.board_corners, 24);  // (5 - 1) x (7 - 1) inner corners
    EXPECT_GE(pose.corners, 12) << photo;
    EXPECT_LE(pose.rms_px, 1.0) << photo;
    EXPECT_GT(pose.t_m[2], 0.1) << photo;  // in front of the camera, at a desk's distance
    EXPECT_LT(pose.t_m[2], 2.0) << photo;
  }
}

TEST(EvalMarker, AWrongDictionaryFindsNoBoard) {
  PROBELESS_REQUIRE_DATA("aruco/choriginal.jpg");
  const auto dir = testing::shared_data_dir() / "aruco";
  const auto cam = eval::read_opencv_camera(dir / "tutorial_camera_charuco.yml");
  const auto pose = eval::find_board_pose(dir / "choriginal.jpg", cam,
                                          parse_board_spec("charuco:5x7:40:20:4x4_50"));
  EXPECT_FALSE(pose.found);
}

TEST(EvalMarker, BadInputsAreClearErrors) {
  const auto dir = testing::scratch_dir();
  EXPECT_THROW(eval::read_opencv_camera(dir / "none.yml"), std::runtime_error);
  std::ofstream(dir / "junk.yml") << "%YAML:1.0\n---\nsomething: 1\n";
  try {
    eval::read_opencv_camera(dir / "junk.yml");
    ADD_FAILURE() << "a file without camera_matrix was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("camera_matrix"), std::string::npos) << e.what();
  }
  eval::BoardCamera cam;
  cam.K = {500, 0, 320, 0, 500, 240, 0, 0, 1};
  cam.distortion = {0, 0, 0, 0, 0};
  std::ofstream(dir / "not_an_image.jpg") << "not a jpeg";
  EXPECT_THROW(eval::find_board_pose(dir / "not_an_image.jpg", cam, kTutorialBoard),
               std::runtime_error);
  EXPECT_THROW(eval::find_board_pose(dir / "x.jpg", cam, parse_board_spec("chessboard:9x6:25")),
               std::invalid_argument);
}

// Runs `probeless ARGS` (through the appliance binary, which hands eval to the lab); returns
// the exit status and, in `output`, stdout and stderr.
int run_probeless(const std::vector<std::string>& args, std::string& output) {
  using namespace std::chrono_literals;
  return testing::run_to_end(testing::probeless_binary(), args, &output, 60s);
}

TEST(EvalMarkerCli, PrintsThePoseAndExitsOneWithoutABoard) {
  PROBELESS_REQUIRE_DATA("aruco/choriginal.jpg");
  const auto dir = testing::shared_data_dir() / "aruco";
  const auto json = testing::scratch_dir() / "marker.json";
  std::string out;
  EXPECT_EQ(run_probeless({"eval", "marker", "--image", dir / "choriginal.jpg", "--camera",
                           dir / "tutorial_camera_charuco.yml", "--json", json},
                          out),
            0)
      << out;
  EXPECT_NE(out.find("board found"), std::string::npos) << out;
  EXPECT_TRUE(std::filesystem::exists(json));
  EXPECT_EQ(
      run_probeless({"eval", "marker", "--image", dir / "choriginal.jpg", "--camera",
                     dir / "tutorial_camera_charuco.yml", "--board", "charuco:5x7:40:20:4x4_50"},
                    out),
      1)
      << out;
  EXPECT_NE(out.find("no board pose"), std::string::npos) << out;
}

}  // namespace
}  // namespace probeless
