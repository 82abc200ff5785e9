// `probeless devices --board NAME`'s "What this config needs" (app/cli/devices_board.hpp):
// says which device, calibration file or chip a board's config lacks on this machine.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/cli/devices_board.hpp"
#include "core/calibration.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "support/test_data.hpp"

namespace probeless::cli {
namespace {

namespace fs = std::filesystem;

const Need* find(const std::vector<Need>& needs, const std::string& prefix) {
  for (const Need& n : needs)
    if (n.what.starts_with(prefix)) return &n;
  return nullptr;
}

ServiceConfig config_with(const std::string& source) {
  ServiceConfig c;
  c.source = source;
  c.display.enabled = false;
  return c;
}

TEST(DevicesNeeds, TheSimNeedsNothing) {
  const auto needs = check_needs(config_with("sim"));
  ASSERT_EQ(needs.size(), 1U);
  EXPECT_TRUE(needs[0].ok);
}

TEST(DevicesNeeds, NamesTheMissingFisheyeCalibrationAndChip) {
  const fs::path dir = testing::scratch_dir();
  const std::string cal = (dir / "calibration.toml").string();
  ServiceConfig c =
      config_with("openni2:+v4l2:/nonexistent/video9?size=512x512&fps=30&calibration=" + cal);
  c.trigger_chip = "no-such-chip";
  auto needs = check_needs(c);
  ASSERT_NE(find(needs, "RGB-D sensor"), nullptr);  // present or not: OpenNI2's Dummy may be
  const Need* fisheye = find(needs, "fisheye /nonexistent/video9");
  ASSERT_NE(fisheye, nullptr);
  EXPECT_FALSE(fisheye->ok);
  EXPECT_NE(fisheye->detail.find("No such file"), std::string::npos) << fisheye->detail;
  const Need* calibration = find(needs, "calibration " + cal);
  ASSERT_NE(calibration, nullptr);
  EXPECT_FALSE(calibration->ok);
  EXPECT_NE(calibration->detail.find("probeless calibrate"), std::string::npos);
  const Need* chip = find(needs, "trigger GPIO chip 'no-such-chip'");
  ASSERT_NE(chip, nullptr);
  EXPECT_FALSE(chip->ok);

  // The unit's calibration (the sim's 512 px fisheye) is there: found, sizes agree.
  std::ofstream(cal) << to_toml(sim::make_sim_rig(sim::SimOptions{}).calibration);
  needs = check_needs(c);
  calibration = find(needs, "calibration " + cal);
  ASSERT_NE(calibration, nullptr);
  EXPECT_TRUE(calibration->ok) << calibration->detail;
  // ... but not at the size the source asks the camera for: both named.
  c.source = "openni2:+v4l2:/nonexistent/video9?size=1280x720&calibration=" + cal;
  calibration = find(needs = check_needs(c), "calibration " + cal);
  ASSERT_NE(calibration, nullptr);
  EXPECT_FALSE(calibration->ok);
  EXPECT_NE(calibration->detail.find("512 x 512"), std::string::npos) << calibration->detail;
  EXPECT_NE(calibration->detail.find("1280 x 720"), std::string::npos) << calibration->detail;

  std::ostringstream out;
  print_needs(out, c);
  EXPECT_NE(out.str().find("MISSING  fisheye /nonexistent/video9"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("missing"), std::string::npos);
}

TEST(DevicesNeeds, AFisheyeWithoutCalibrationIsMissingOne) {
  const auto needs = check_needs(config_with("openni2:+v4l2:/nonexistent/video9"));
  const Need* calibration = find(needs, "calibration");
  ASSERT_NE(calibration, nullptr);
  EXPECT_FALSE(calibration->ok);
}

}  // namespace
}  // namespace probeless::cli
