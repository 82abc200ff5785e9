// `probeless calibrate` as a user runs it: the appliance binary hands it to the lab, the JSON
// and TOML it writes (loaded back with the service's reader), and its errors.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "core/camera/kannala_brandt.hpp"
#include "core/camera/pinhole.hpp"
#include "drivers/io/png.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "drivers/replay/recording_writer.hpp"
#include "integration/calibrate/rendered_board.hpp"
#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::string binary() {
  return testing::probeless_binary();
}

// Runs `program` with `args`; returns the exit status (-1 on timeout). `output` gets stdout
// and stderr.
int run_program(const std::string& program, const std::vector<std::string>& args,
                std::string* output = nullptr) {
  return testing::run_to_end(program, args, output, 300s);
}

int run(const std::vector<std::string>& args, std::string* output = nullptr) {
  std::vector<std::string> all{"calibrate"};
  all.insert(all.end(), args.begin(), args.end());
  return run_program(binary(), all, output);
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// A folder with the four photos of OpenCV's ChArUco tutorial (symlinks: nothing is copied).
fs::path tutorial_photos() {
  const fs::path dir = testing::scratch_dir() / "aruco";
  fs::create_directories(dir);
  for (int i = 0; i < 4; ++i) {
    const std::string name = "img_0" + std::to_string(i) + ".jpg";
    fs::create_symlink(testing::shared_data_dir() / "aruco" / name, dir / name);
  }
  return dir;
}

TEST(Calibrate, CharucoPhotosGiveThePinholeJsonAndARigFileTheServiceLoads) {
  PROBELESS_REQUIRE_DATA("aruco/img_00.jpg");
  const fs::path out = testing::scratch_dir();
  std::string log;
  ASSERT_EQ(run({"--images", tutorial_photos().string(), "--board", "charuco:5x7:40:20:6x6_250",
                 "--camera-out", (out / "rgb.toml").string(), "--views-out",
                 (out / "views").string(), "--json", (out / "r.json").string()},
                &log),
            0)
      << log;
  EXPECT_NE(log.find("[4/4] img_03.jpg: 24 of 24 corners"), std::string::npos) << log;
  const auto j = read_json(out / "r.json");
  EXPECT_EQ(j["model"], "pinhole");
  EXPECT_NEAR(j["fx"].get<double>(), 452.51, 452.51 * 0.02);
  EXPECT_NEAR(j["fy"].get<double>(), 456.77, 456.77 * 0.02);
  EXPECT_NEAR(j["cx"].get<double>(), 317.70, 317.70 * 0.02);
  EXPECT_NEAR(j["cy"].get<double>(), 277.75, 277.75 * 0.02);
  EXPECT_LE(j["rms_px"].get<double>(), 0.5);
  EXPECT_EQ(j["distortion"].size(), 5u);
  EXPECT_EQ(j["views_used"], 4);
  ASSERT_EQ(j["views"].size(), 4u);
  EXPECT_EQ(j["views"][0]["file"], "img_00.jpg");
  EXPECT_LE(j["views"][0]["rms_px"].get<double>(), 0.5);
  const RigCalibration rig = replay::load_rig_calibration(out / "rgb.toml");
  EXPECT_EQ(rig.rgb.intrinsics().fx, j["fx"].get<double>());
  EXPECT_EQ(rig.rgb.distortion().k1, j["distortion"][0].get<double>());
  for (int i = 0; i < 4; ++i)
    EXPECT_GT(fs::file_size(out / "views" / ("img_0" + std::to_string(i) + ".png")), 1000u);
}

TEST(Calibrate, FisheyeChessboardWithKannalaBrandt) {
  PROBELESS_REQUIRE_DATA("fisheye/chessboard");
  const fs::path out = testing::scratch_dir();
  std::string log;
  ASSERT_EQ(
      run({"--images", (testing::shared_data_dir() / "fisheye/chessboard").string(), "--board",
           "chessboard:9x6:25", "--model", "kannala-brandt", "--json", (out / "f.json").string()},
          &log),
      0)
      << log;
  const auto j = read_json(out / "f.json");
  EXPECT_EQ(j["model"], "kannala-brandt");
  EXPECT_EQ(j["views_used"], 8);
  EXPECT_LE(j["rms_px"].get<double>(), 0.3);
  EXPECT_NEAR(j["fx"].get<double>(), 309, 309 * 0.02);
  EXPECT_EQ(j["distortion"].size(), 4u);
}

TEST(Calibrate, OcamCalibImport) {
  PROBELESS_REQUIRE_DATA("fisheye/ocamcalib/calib_results_fisheye.txt");
  const fs::path out = testing::scratch_dir();
  std::string log;
  ASSERT_EQ(
      run({"--import-ocam",
           (testing::shared_data_dir() / "fisheye/ocamcalib/calib_results_fisheye.txt").string(),
           "--camera-out", (out / "fisheye.toml").string()},
          &log),
      0)
      << log;
  std::ifstream in(out / "fisheye.toml");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  EXPECT_NE(text.find("model = \"ocam\""), std::string::npos) << text;
  EXPECT_NE(text.find("height = 768"), std::string::npos) << text;
}

struct BadInput {
  std::vector<std::string> args;
  std::string message;
};

TEST(Calibrate, BadInputsAreClearErrors) {
  const fs::path dir = testing::scratch_dir();
  fs::create_directories(dir / "empty");
  fs::create_directories(dir / "broken");
  std::ofstream(dir / "broken" / "a.jpg") << "not a jpeg";
  fs::create_directories(dir / "blank");
  write_png(dir / "blank" / "a.png", ImageGray8(64, 48, 128));
  write_png(dir / "blank" / "b.png", ImageGray8(64, 48, 200));
  const std::string board = "charuco:5x7:40:20:6x6_250";
  const std::vector<BadInput> cases{
      {{"--images", (dir / "missing").string(), "--board", board}, "missing: no such directory"},
      {{"--images", (dir / "empty").string(), "--board", board}, "empty: no images in it"},
      {{"--images", (dir / "broken").string(), "--board", board}, "a.jpg: cannot read the image"},
      {{"--images", (dir / "blank").string(), "--board", board},
       "too few views: the board was found in 0 of 2 images"},
      {{"--images", (dir / "blank").string(), "--board", board, "--model", "fisheye"},
       "--model 'fisheye': expected pinhole or kannala-brandt"},
      {{"--images", (dir / "blank").string(), "--board", "charuco:5x7:40:50:6x6_250"},
       "the marker must be smaller than its square"},
      {{"--images", (dir / "blank").string()}, "--board SPEC is needed"},
      {{"--board", board}, "calibrate takes one of --images DIR"},
      {{"--images", (dir / "blank").string(), "--recording", dir.string(), "--board", board},
       "calibrate takes one of --images DIR"},
      {{"--rgb-images", (dir / "blank").string(), "--board", board, "--out", "x.toml"},
       "--rgb-images and --fisheye-images go together"},
      {{"--rgb-images", (dir / "blank").string(), "--fisheye-images", (dir / "blank").string(),
        "--board", board},
       "--out FILE is needed"},
      {{"--recording", (dir / "empty").string(), "--board", board, "--out", "x.toml"},
       "manifest.toml"},
      {{"--import-ocam", (dir / "missing.txt").string(), "--camera-out", "x.toml"},
       "no such OCamCalib file"},
      {{"--import-ocam", (dir / "missing.txt").string()}, "--import-ocam needs --camera-out"},
      {{"--images", (dir / "blank").string(), "--board", board, "--intrinsics", "x.toml"},
       "--intrinsics goes with --recording or --rgb-images"},
  };
  for (const BadInput& c : cases) {
    std::string log;
    EXPECT_EQ(run(c.args, &log), 1) << log;
    EXPECT_NE(log.find(c.message), std::string::npos) << "expected \"" << c.message << "\" in:\n"
                                                      << log;
  }
}

TEST(Calibrate, WithoutTheLabTheAppliancesErrorNamesTheLabPackage) {
  const fs::path dir = testing::scratch_dir();
  fs::copy_file(binary(), dir / "probeless");  // the binary alone, no probeless-lab beside it
  std::string log;
  EXPECT_EQ(run_program((dir / "probeless").string(), {"calibrate", "--help"}, &log), 1) << log;
  EXPECT_NE(log.find("'probeless calibrate' is a command of the lab (the probeless-lab package"),
            std::string::npos)
      << log;
  // And with it, the command is there.
  EXPECT_EQ(run({"--help"}, &log), 0) << log;
  EXPECT_NE(log.find("--import-ocam"), std::string::npos) << log;
}

// The rig end to end on rendered views with known truth: both cameras' images of a ChArUco
// board, the folder form, the TOML loaded back (issue #18's bar: intrinsics within 0.5 %,
// extrinsics within 2 mm and 0.2 degrees; see below for what this test reaches).
// A rig with known truth and its views of a ChArUco board, ray-cast through both models.
struct RenderedRig {
  PinholeCamera rgb{PinholeIntrinsics{640, 480, 525, 525, 319.5, 239.5},
                    BrownDistortion{0.04, -0.08, 0, 0, 0}};
  KannalaBrandtCamera fisheye{
      KannalaBrandtParams{800, 800, 255, 255, 399.5, 399.5, {0.02, -0.005, 0, 0}, 1.66}};
  Pose T_rgb_fisheye;  // tilted up by 60 deg, 6 cm above and 1 cm behind the colour camera
  std::vector<std::pair<ImageGray8, ImageGray8>> views;  // colour, fisheye
  static constexpr const char* kBoard = "charuco:7x5:50:37:4x4_50";
};

RenderedRig render_rig(int count) {
  using namespace calib::testing;
  RenderedRig rig;
  rig.T_rgb_fisheye.rotation = Eigen::AngleAxisd(60 * M_PI / 180, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(2 * M_PI / 180, Eigen::Vector3d::UnitY());
  rig.T_rgb_fisheye.translation = {0.02, -0.06, -0.01};
  const Pose T_fisheye_rgb = rig.T_rgb_fisheye.inverse();
  constexpr int kPixelsPerSquare = 60;
  const ImageGray8 print =
      calib::board_image(parse_board_spec(RenderedRig::kBoard), kPixelsPerSquare);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> tilt(-35, 35), spin(-30, 30), xy(-0.1, 0.1), z(0.5, 0.7);
  const Eigen::Vector3d centre_on_board(0.175, 0.125, 0);
  for (int i = 0; i < count; ++i) {
    Pose T_rgb_board;
    T_rgb_board.rotation = Eigen::AngleAxisd(tilt(rng) * M_PI / 180, Eigen::Vector3d::UnitX()) *
                           Eigen::AngleAxisd(tilt(rng) * M_PI / 180, Eigen::Vector3d::UnitY()) *
                           Eigen::AngleAxisd(spin(rng) * M_PI / 180, Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d centre(xy(rng), xy(rng) - 0.05, z(rng));
    T_rgb_board.translation = centre - T_rgb_board.rotation * centre_on_board;
    rig.views.emplace_back(
        render_board(rig.rgb, T_rgb_board, print, 0.05, kPixelsPerSquare, 0),
        render_board(rig.fisheye, T_fisheye_rgb * T_rgb_board, print, 0.05, kPixelsPerSquare, 0));
  }
  return rig;
}

TEST(Calibrate, RigFromRenderedViewsRecoversTheTruth) {
  const RenderedRig rendered = render_rig(14);
  const PinholeCamera& rgb = rendered.rgb;
  const KannalaBrandtCamera& fisheye = rendered.fisheye;
  const Pose& T_rgb_fisheye = rendered.T_rgb_fisheye;
  const fs::path dir = testing::scratch_dir();
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "fisheye");
  for (std::size_t i = 0; i < rendered.views.size(); ++i) {
    const std::string name = "pair_" + std::to_string(i) + ".png";
    write_png(dir / "rgb" / name, rendered.views[i].first);
    write_png(dir / "fisheye" / name, rendered.views[i].second);
  }
  std::string log;
  ASSERT_EQ(
      run({"--rgb-images", (dir / "rgb").string(), "--fisheye-images", (dir / "fisheye").string(),
           "--board", "charuco:7x5:50:37:4x4_50", "--out", (dir / "rig.toml").string(), "--json",
           (dir / "rig.json").string(), "--views-out", (dir / "views").string()},
          &log),
      0)
      << log;
  const RigCalibration rig = replay::load_rig_calibration(dir / "rig.toml");
  const auto& k = rig.rgb.intrinsics();
  EXPECT_NEAR(k.fx, 525, 525 * 0.005) << log;
  EXPECT_NEAR(k.fy, 525, 525 * 0.005);
  EXPECT_NEAR(k.cx, 319.5, 640 * 0.005);
  EXPECT_NEAR(k.cy, 239.5, 480 * 0.005);
  const auto* kb = dynamic_cast<const KannalaBrandtCamera*>(rig.fisheye.get());
  ASSERT_NE(kb, nullptr);
  EXPECT_NEAR(kb->params().fx, 255, 255 * 0.005);
  EXPECT_NEAR(kb->params().fy, 255, 255 * 0.005);
  EXPECT_NEAR(kb->params().cx, 399.5, 800 * 0.005);
  EXPECT_NEAR(kb->params().cy, 399.5, 800 * 0.005);
  EXPECT_TRUE(rig.T_rig_rgb.translation.isZero());
  const double t_err = (rig.T_rig_fisheye.translation - T_rgb_fisheye.translation).norm();
  const double r_err =
      rig.T_rig_fisheye.rotation.angularDistance(T_rgb_fisheye.rotation) * 180 / M_PI;
  // Issue #18's 2 mm and 0.2 deg, with the intrinsics from the same rendered pairs. Measured
  // 0.46 mm and 0.093 deg; 2.5 mm and 0.35 deg while OpenCV's ChArUco corners were taken as
  // they came, +0.5 px in x and in y (board_detector.cpp).
  EXPECT_LT(t_err, 0.002) << t_err * 1000 << " mm\n" << log;
  EXPECT_LT(r_err, 0.2) << r_err << " deg\n" << log;
  const auto j = read_json(dir / "rig.json");
  EXPECT_EQ(j["views_used"], 14) << log;
  EXPECT_LT(j["rms_px"].get<double>(), 0.5);
  EXPECT_TRUE(fs::exists(dir / "views" / "fisheye_pair_0.png"));
  std::cout << log << "T_rig_fisheye error: " << t_err * 1000 << " mm, " << r_err << " deg\n";

  // With the cameras' models given (--intrinsics, here the true ones), only the extrinsics
  // are solved: issue #18's 2 mm and 0.2 degrees.
  RigCalibration truth;
  truth.rgb = rgb;
  truth.fisheye = std::make_shared<KannalaBrandtCamera>(fisheye);
  std::ofstream(dir / "truth.toml") << to_toml(truth);
  ASSERT_EQ(run({"--rgb-images", (dir / "rgb").string(), "--fisheye-images",
                 (dir / "fisheye").string(), "--board", "charuco:7x5:50:37:4x4_50", "--intrinsics",
                 (dir / "truth.toml").string(), "--out", (dir / "extrinsics.toml").string()},
                &log),
            0)
      << log;
  const RigCalibration fixed = replay::load_rig_calibration(dir / "extrinsics.toml");
  EXPECT_EQ(fixed.rgb.intrinsics(), rgb.intrinsics());
  const double t_fixed = (fixed.T_rig_fisheye.translation - T_rgb_fisheye.translation).norm();
  const double r_fixed =
      fixed.T_rig_fisheye.rotation.angularDistance(T_rgb_fisheye.rotation) * 180 / M_PI;
  EXPECT_LT(t_fixed, 0.002) << t_fixed * 1000 << " mm\n" << log;
  EXPECT_LT(r_fixed, 0.2) << r_fixed << " deg\n" << log;
  std::cout << log << "with the true intrinsics: " << t_fixed * 1000 << " mm, " << r_fixed
            << " deg\n";
}

}  // namespace
}  // namespace probeless

namespace probeless {
namespace {

// The same from a recording as `probeless record` writes it: colour frames, raw 12-bit
// fisheye frames 5 ms later (and one 50 ms off, with nothing to pair), the models given.
TEST(Calibrate, RigFromARecordingWithGivenModels) {
  const RenderedRig rendered = render_rig(8);
  const fs::path dir = testing::scratch_dir();
  RigCalibration recorded;
  recorded.rgb = rendered.rgb;
  recorded.fisheye = std::make_shared<KannalaBrandtCamera>(rendered.fisheye);
  recorded.depth_baseline_m = 0.05;
  {
    replay::RecordingWriter writer(dir / "rec", recorded);
    for (std::size_t i = 0; i < rendered.views.size(); ++i) {
      const auto& [grey, fisheye_grey] = rendered.views[i];
      RgbdFrame rgbd;
      rgbd.sequence = i;
      rgbd.timestamp_ns = static_cast<TimestampNs>(i) * 100'000'000;
      rgbd.colour = ImageRGB8(grey.width(), grey.height());
      for (std::size_t p = 0; p < grey.pixel_count(); ++p)
        for (int c = 0; c < 3; ++c) rgbd.colour.data()[3 * p + c] = grey.data()[p];
      rgbd.depth = DepthImage(grey.width(), grey.height(), 1000);
      writer.append(rgbd);
      FisheyeFrame frame;
      frame.sequence = i;
      frame.timestamp_ns = rgbd.timestamp_ns + 5'000'000;
      frame.black_level = 64;
      frame.raw = ImageRGB16(fisheye_grey.width(), fisheye_grey.height());
      for (std::size_t p = 0; p < fisheye_grey.pixel_count(); ++p) {
        const double linear = std::pow(fisheye_grey.data()[p] / 255.0, 2.2);
        for (int c = 0; c < 3; ++c)
          frame.raw.data()[3 * p + c] = static_cast<std::uint16_t>(64 + 3000 * linear);
      }
      writer.append(frame);
      frame.timestamp_ns += 45'000'000;  // 50 ms from either colour frame: not paired
      frame.sequence += 100;
      writer.append(frame);
    }
    writer.finish();
  }
  std::ofstream(dir / "models.toml") << to_toml(recorded);
  std::string log;
  ASSERT_EQ(
      run({"--recording", (dir / "rec").string(), "--board", RenderedRig::kBoard, "--intrinsics",
           (dir / "models.toml").string(), "--out", (dir / "rig.toml").string()},
          &log),
      0)
      << log;
  EXPECT_NE(log.find("[8/8] frame_000007: colour 24 of 24 corners, fisheye 24 of 24 corners"),
            std::string::npos)
      << log;
  const RigCalibration rig = replay::load_rig_calibration(dir / "rig.toml");
  EXPECT_EQ(rig.depth_baseline_m, 0.05);  // kept from the recording's calibration
  const double t_err = (rig.T_rig_fisheye.translation - rendered.T_rgb_fisheye.translation).norm();
  const double r_err =
      rig.T_rig_fisheye.rotation.angularDistance(rendered.T_rgb_fisheye.rotation) * 180 / M_PI;
  EXPECT_LT(t_err, 0.002) << t_err * 1000 << " mm\n" << log;
  EXPECT_LT(r_err, 0.2) << r_err << " deg\n" << log;
  std::cout << log << "from the recording: " << t_err * 1000 << " mm, " << r_err << " deg\n";
}

}  // namespace
}  // namespace probeless
