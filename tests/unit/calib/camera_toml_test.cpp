// The camera files calibrate writes are what the service reads: each is loaded back with the
// real reader (drivers/replay/calibration_file.hpp -> core/calibration.hpp).
#include "lab/calib/camera_toml.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/camera/kannala_brandt.hpp"
#include "core/camera/ocam.hpp"
#include "core/camera/pinhole.hpp"
#include "core/error.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "support/test_data.hpp"

namespace probeless::calib {
namespace {
namespace fs = std::filesystem;

std::shared_ptr<const PinholeCamera> pinhole() {
  return std::make_shared<PinholeCamera>(
      PinholeIntrinsics{640, 480, 459.71057340226861, 464.16870379012013, 317.94, 275.95},
      BrownDistortion{0.1321639748355655, -1.2508368240475498, 0.00038, -0.000995, 3.62178971});
}

std::shared_ptr<const KannalaBrandtCamera> fisheye() {
  return std::make_shared<KannalaBrandtCamera>(KannalaBrandtParams{
      640,
      640,
      309.30812532020474,
      309.2300382115375,
      325.2254,
      312.4067,
      {-0.038844093144332625, 0.09800522921401725, -0.18807656415459142, 0.11840620567950896},
      1.2599});
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(CameraToml, APinholeAloneIsAnRgbdOnlyRigTheServiceLoads) {
  const fs::path file = probeless::testing::scratch_dir() / "rgb.toml";
  write_camera_toml(file, pinhole());
  const RigCalibration rig = replay::load_rig_calibration(file);
  EXPECT_EQ(rig.rgb.intrinsics(), pinhole()->intrinsics());
  EXPECT_EQ(rig.rgb.distortion(), pinhole()->distortion());
  EXPECT_EQ(rig.fisheye, nullptr);
  EXPECT_TRUE(rig.T_rig_rgb.translation.isZero());
}

TEST(CameraToml, AFisheyeIsAddedToAnExistingRigAndLoadsBack) {
  const fs::path file = probeless::testing::scratch_dir() / "rig.toml";
  write_camera_toml(file, pinhole());
  const std::string said = write_camera_toml(file, fisheye());
  EXPECT_NE(said.find("replaced the fisheye"), std::string::npos) << said;
  const RigCalibration rig = replay::load_rig_calibration(file);
  EXPECT_EQ(rig.rgb.intrinsics(), pinhole()->intrinsics());  // kept
  const auto* kb = dynamic_cast<const KannalaBrandtCamera*>(rig.fisheye.get());
  ASSERT_NE(kb, nullptr);
  EXPECT_EQ(kb->params(), fisheye()->params());  // bit for bit
}

TEST(CameraToml, AFisheyeAloneIsTheFisheyeTableOfARigFile) {
  const fs::path dir = probeless::testing::scratch_dir();
  write_camera_toml(dir / "rgb.toml", pinhole());
  write_camera_toml(dir / "fisheye.toml", fisheye());
  const std::string table = read_text(dir / "fisheye.toml");
  EXPECT_EQ(table.find("[rgb]"), std::string::npos);
  // Joined with the colour camera's file it is a rig calibration the reader takes.
  const RigCalibration rig =
      parse_rig_calibration(read_text(dir / "rgb.toml") + "\n" + table, "joined");
  const auto* kb = dynamic_cast<const KannalaBrandtCamera*>(rig.fisheye.get());
  ASSERT_NE(kb, nullptr);
  EXPECT_EQ(kb->params(), fisheye()->params());
}

TEST(CameraToml, AFileThatIsNotARigCalibrationIsNotOverwritten) {
  const fs::path file = probeless::testing::scratch_dir() / "notes.toml";
  std::ofstream(file) << "title = \"my notes\"\n";
  try {
    write_camera_toml(file, pinhole());
    FAIL() << "overwrote a file that is not a rig calibration";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("exists and is not a rig calibration"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(read_text(file), "title = \"my notes\"\n");
}

TEST(CameraToml, OcamCalibFileImportedAsItIs) {
  PROBELESS_REQUIRE_DATA("fisheye/ocamcalib/calib_results_fisheye.txt");
  const fs::path ocam =
      probeless::testing::shared_data_dir() / "fisheye/ocamcalib/calib_results_fisheye.txt";
  const fs::path file = probeless::testing::scratch_dir() / "rig.toml";
  write_camera_toml(file, pinhole());
  write_camera_toml(file, read_ocam_file(ocam));
  const RigCalibration rig = replay::load_rig_calibration(file);
  const auto* loaded = dynamic_cast<const OCamCamera*>(rig.fisheye.get());
  ASSERT_NE(loaded, nullptr);
  EXPECT_EQ(loaded->params(), OCamCamera::parse(read_text(ocam)).params());
}

TEST(CameraToml, OcamFileErrors) {
  const fs::path dir = probeless::testing::scratch_dir();
  try {
    read_ocam_file(dir / "missing.txt");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no such OCamCalib file"), std::string::npos);
  }
  std::ofstream(dir / "big.txt") << std::string(2 << 20, '1');
  try {
    read_ocam_file(dir / "big.txt");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("too large for an OCamCalib"), std::string::npos);
  }
  std::ofstream(dir / "bad.txt") << "#pol\n3 -200 x 0.0015\n";
  EXPECT_THROW(read_ocam_file(dir / "bad.txt"), ParseError);
}

}  // namespace
}  // namespace probeless::calib
