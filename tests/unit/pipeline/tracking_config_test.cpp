// [tracking] and [world] of the service config (issue #17, docs/configuration.md).
#include <gtest/gtest.h>

#include <string>

#include "app/pipeline/service_config.hpp"
#include "core/error.hpp"

namespace probeless {
namespace {

std::string error_of(const std::string& toml) {
  try {
    parse_service_config(toml, "t.toml");
  } catch (const ParseError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(TrackingConfig, DefaultsAreDenseTrackingInTheRigsWorld) {
  const ServiceConfig c = parse_service_config("");
  EXPECT_EQ(c.tracking.method, "dense");
  EXPECT_EQ(c.tracking.device, "cpu");
  EXPECT_EQ(c.world.anchor, "rig");
  EXPECT_EQ(c.world.marker, "charuco:5x4:80:60:4x4_50");
}

TEST(TrackingConfig, ReadsEveryKey) {
  const ServiceConfig c = parse_service_config(
      "[tracking]\nmethod = \"truth\"\nmin_depth_m = 0.5\nmax_depth_m = 3\n"
      "[world]\nanchor = \"marker\"\nmarker = \"aruco:7:150:4x4_50\"\nmax_step_mm = 1.5\n"
      "floor_max_tilt_deg = 20\n");
  EXPECT_EQ(c.tracking.method, "truth");
  EXPECT_DOUBLE_EQ(c.tracking.min_depth_m, 0.5);
  EXPECT_DOUBLE_EQ(c.tracking.max_depth_m, 3);
  EXPECT_EQ(c.world.anchor, "marker");
  EXPECT_EQ(c.world.marker, "aruco:7:150:4x4_50");
  EXPECT_DOUBLE_EQ(c.world.max_step_mm, 1.5);
  EXPECT_DOUBLE_EQ(c.world.floor_max_tilt_deg, 20);
  for (const char* m : {"dense", "off"})
    EXPECT_EQ(
        parse_service_config(std::string("[tracking]\nmethod = \"") + m + "\"\n").tracking.method,
        m);
  EXPECT_EQ(parse_service_config("[world]\nanchor = \"floor\"\n").world.anchor, "floor");
  EXPECT_EQ(parse_service_config("[tracking]\ndevice = \"opencl\"\n").tracking.device, "opencl");
  EXPECT_DOUBLE_EQ(parse_service_config("[tracking]\nrolling_shutter_readout_s = 0.028\n")
                       .tracking.rolling_shutter_readout_s,
                   0.028);
}

TEST(TrackingConfig, BadValuesAreClearErrorsAtTheirLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"[tracking]\nmethod = \"icp\"\n", "is not one of \"dense\", \"truth\", \"off\""},
      {"[tracking]\nmethod = 1\n", "expected a string"},
      {"[tracking]\nmin_depth_m = 5\n", "0 < min_depth_m < max_depth_m"},
      {"[tracking]\nmax_depth_m = 50\n", "max_depth_m <= 20"},
      {"[tracking]\nrate = 5\n", "rate"},
      {"[tracking]\ndevice = \"gpu\"\n", "is not \"cpu\" or \"opencl\""},
      {"[tracking]\nrolling_shutter_readout_s = -0.01\n", "rolling_shutter_readout_s"},
      {"[world]\nanchor = \"table\"\n", "is not one of \"marker\", \"floor\", \"rig\""},
      {"[world]\nmarker = \"charuco:5x4:80\"\n", "four fields"},
      {"[world]\nmarker = \"aruco:50:100:4x4_50\"\n", "0..49"},
      {"[world]\nmarker = \"chessboard:9x6:25\"\n", "cannot anchor the world"},
      {"[world]\nmax_step_mm = 0\n", "max_step_mm"},
      {"[world]\nfloor_max_tilt_deg = 90\n", "floor_max_tilt_deg"},
  };
  for (const auto& [toml, why] : cases) {
    const std::string e = error_of(toml);
    EXPECT_NE(e.find(why), std::string::npos) << toml << " -> " << e;
    EXPECT_NE(e.find("t.toml"), std::string::npos) << e;
  }
}

}  // namespace
}  // namespace probeless
