// One camera's intrinsics from board views: synthetic views with known truth for both
// models, the clear errors, and the quality bar of issue #18 on the shared real photos.
#include "lab/calib/intrinsics.hpp"

#include <gtest/gtest.h>

#include "core/camera/kannala_brandt.hpp"
#include "core/camera/pinhole.hpp"
#include "lab/calib/view_sources.hpp"
#include "support/test_data.hpp"
#include "unit/calib/synthetic_board.hpp"

namespace probeless::calib {
namespace {
using namespace probeless::calib::testing;

std::vector<BoardView> synthetic_views(const CameraModel& camera, double depth, int count,
                                       double tilt_range, std::mt19937& rng) {
  std::uniform_real_distribution<double> xy(-0.1, 0.1), tilt(-tilt_range, tilt_range),
      spin(-180, 180);
  std::vector<BoardView> views;
  while (static_cast<int>(views.size()) < count) {
    const Pose pose = board_pose({xy(rng), xy(rng), depth}, tilt(rng), tilt(rng), spin(rng));
    auto px = project_board(camera, pose, 0.1, rng);
    if (!px.empty()) views.push_back(board_view("v" + std::to_string(views.size()), camera, px));
  }
  return views;
}

TEST(Intrinsics, PinholeRecoversItsCameraWithin0_5Percent) {
  const PinholeCamera truth(PinholeIntrinsics{640, 480, 525, 523, 321, 242},
                            BrownDistortion{0.08, -0.2, 0.001, -0.0015, 0.05});
  std::mt19937 rng(1);
  const Intrinsics in =
      calibrate_intrinsics(synthetic_views(truth, 0.7, 12, 35, rng), LensModel::Pinhole);
  EXPECT_NEAR(in.fx, 525, 525 * 0.005);
  EXPECT_NEAR(in.fy, 523, 523 * 0.005);
  EXPECT_NEAR(in.cx, 321, 640 * 0.005);
  EXPECT_NEAR(in.cy, 242, 480 * 0.005);
  EXPECT_LT(in.rms_px, 0.2);  // 0.1 px noise per axis
  ASSERT_EQ(in.distortion.size(), 5u);
  EXPECT_NEAR(in.distortion[0], 0.08, 0.02);
  EXPECT_EQ(in.views.size(), 12u);
  const auto* camera = dynamic_cast<const PinholeCamera*>(in.camera().get());
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ(camera->intrinsics().fx, in.fx);
  EXPECT_EQ(camera->distortion().k1, in.distortion[0]);
}

TEST(Intrinsics, KannalaBrandtRecoversItsCameraWithin0_5Percent) {
  const KannalaBrandtCamera truth(
      KannalaBrandtParams{800, 800, 250, 251, 402, 397, {0.03, -0.01, 0.002, 0}, 1.7});
  std::mt19937 rng(2);
  const auto views = synthetic_views(truth, 0.35, 12, 40, rng);
  const Intrinsics in = calibrate_intrinsics(views, LensModel::KannalaBrandt);
  EXPECT_NEAR(in.fx, 250, 250 * 0.005);
  EXPECT_NEAR(in.fy, 251, 251 * 0.005);
  EXPECT_NEAR(in.cx, 402, 800 * 0.005);
  EXPECT_NEAR(in.cy, 397, 800 * 0.005);
  EXPECT_LT(in.rms_px, 0.2);
  ASSERT_EQ(in.distortion.size(), 4u);
  const auto* camera = dynamic_cast<const KannalaBrandtCamera*>(in.camera().get());
  ASSERT_NE(camera, nullptr);
  // The model's domain (max_theta) covers every corner it was fitted to.
  for (const BoardView& v : views)
    for (const auto& px : v.pixels) ASSERT_TRUE(camera->unproject(px)) << v.name;
}

TEST(Intrinsics, TooFewViewsIsAClearError) {
  const PinholeCamera truth;
  std::mt19937 rng(3);
  try {
    calibrate_intrinsics(synthetic_views(truth, 0.7, 2, 30, rng), LensModel::Pinhole);
    FAIL() << "two views were accepted";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("too few views: the board was found in 2 images, at "
                                         "least 3 are needed"),
              std::string::npos)
        << e.what();
  }
}

TEST(Intrinsics, ParallelBoardsAreDegenerate) {
  // The same board orientation, moved about: no constraint beyond the first view's.
  const PinholeCamera truth;
  std::mt19937 rng(4);
  std::vector<BoardView> views;
  for (int i = 0; i < 5; ++i) {
    const Pose pose = board_pose({0.05 * i - 0.1, 0.02 * i, 0.6 + 0.05 * i}, 20, 10, 15);
    views.push_back(
        board_view("v" + std::to_string(i), truth, project_board(truth, pose, 0.1, rng)));
  }
  try {
    calibrate_intrinsics(views, LensModel::Pinhole);
    FAIL() << "parallel boards were accepted";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("degenerate views"), std::string::npos) << e.what();
  }
}

TEST(Intrinsics, ViewsOfDifferentSizesAreAnError) {
  const PinholeCamera truth;
  std::mt19937 rng(5);
  auto views = synthetic_views(truth, 0.7, 4, 30, rng);
  views[2].width = 1280;
  EXPECT_THROW(calibrate_intrinsics(views, LensModel::Pinhole), CalibrationError);
}

TEST(Intrinsics, LensModelNames) {
  EXPECT_EQ(parse_lens_model("pinhole"), LensModel::Pinhole);
  EXPECT_EQ(parse_lens_model("kannala-brandt"), LensModel::KannalaBrandt);
  EXPECT_EQ(parse_lens_model("kannala_brandt"), LensModel::KannalaBrandt);
  EXPECT_FALSE(parse_lens_model("ocam"));
  EXPECT_FALSE(parse_lens_model(""));
}

// Issue #18's quality bar on the real photos of ../shared/data.
std::vector<BoardView> detect_all(const std::vector<std::filesystem::path>& files,
                                  const std::string& spec) {
  const BoardDetector detector(parse_board_spec(spec));
  std::vector<BoardView> views;
  for (const auto& f : files)
    if (auto v = detector.detect(read_gray_image(f), f.filename().string()))
      views.push_back(std::move(*v));
  return views;
}

TEST(IntrinsicsOnRealPhotos, CharucoTutorialWithin2PercentOfOpenCVsFile) {
  PROBELESS_REQUIRE_DATA("aruco/img_00.jpg");
  const auto dir = probeless::testing::shared_data_dir() / "aruco";
  std::vector<std::filesystem::path> files;
  for (int i = 0; i < 4; ++i) files.push_back(dir / ("img_0" + std::to_string(i) + ".jpg"));
  const auto views = detect_all(files, "charuco:5x7:40:20:6x6_250");
  ASSERT_EQ(views.size(), 4u);
  const Intrinsics in = calibrate_intrinsics(views, LensModel::Pinhole);
  // tutorial_camera_charuco.yml: what OpenCV's calibrateCameraCharuco found from them.
  EXPECT_NEAR(in.fx, 452.51, 452.51 * 0.02);
  EXPECT_NEAR(in.fy, 456.77, 456.77 * 0.02);
  EXPECT_NEAR(in.cx, 317.70, 317.70 * 0.02);
  EXPECT_NEAR(in.cy, 277.75, 277.75 * 0.02);
  EXPECT_LE(in.rms_px, 0.5);
  EXPECT_EQ(in.views.size(), 4u);
}

TEST(IntrinsicsOnRealPhotos, FisheyeChessboardAllViewsUnder0_3Px) {
  PROBELESS_REQUIRE_DATA("fisheye/chessboard");
  const auto files = list_images(probeless::testing::shared_data_dir() / "fisheye/chessboard");
  ASSERT_EQ(files.size(), 8u);
  // 9 x 6 inner corners; the square's size is unknown and does not change the intrinsics.
  const auto views = detect_all(files, "chessboard:9x6:25");
  ASSERT_EQ(views.size(), 8u);
  const Intrinsics in = calibrate_intrinsics(views, LensModel::KannalaBrandt);
  EXPECT_EQ(in.views.size(), 8u);
  EXPECT_LE(in.rms_px, 0.3);
  EXPECT_NEAR(in.fx, 309, 309 * 0.02);  // what cv::fisheye::calibrate gives on its own
  EXPECT_NEAR(in.fy, 309, 309 * 0.02);
  for (const ViewFit& v : in.views) EXPECT_LT(v.rms_px, 0.5) << v.name;
}

}  // namespace
}  // namespace probeless::calib
