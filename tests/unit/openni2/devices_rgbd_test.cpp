// The "RGB-D sensors" section of `probeless devices` on a machine without sensors: it says
// so for OpenNI2 and for USB, naming the vendors it looked for.
#include "app/cli/devices_rgbd.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "drivers/openni2/openni2_runtime.hpp"

namespace probeless::cli {
namespace {

TEST(DevicesRgbd, SaysWhatItLookedForAndFound) {
  std::ostringstream out;
  print_rgbd_sensors(out, {0x1d27, 0x2bc5});
  const std::string text = out.str();
  EXPECT_EQ(text.rfind("RGB-D sensors\n", 0), 0u) << text;
  EXPECT_NE(text.find("USB (vendors 1d27:2bc5): "), std::string::npos) << text;
  if (openni2::list_openni_devices().empty()) {
    EXPECT_NE(text.find("OpenNI2: no device"), std::string::npos) << text;
  } else {
    EXPECT_NE(text.find("colour: "), std::string::npos) << text;  // a device lists its modes
  }
}

}  // namespace
}  // namespace probeless::cli
