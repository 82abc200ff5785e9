// The libcamera spec's options and their errors (no camera needed).
#include "drivers/libcamera/libcamera_options.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace probeless::libcam {
namespace {

TEST(LibcameraOptions, ParsesCameraIdAndOptions) {
  const LibcameraOptions o = parse_libcamera_options(
      "platform/vimc.0 Sensor B?size=320x240&format=BGR888,buffers=6&reopen_ms=100&stall_ms=500");
  EXPECT_EQ(o.camera_id, "platform/vimc.0 Sensor B");  // ids hold '/', ' ' and '.'
  EXPECT_EQ(o.width, 320);
  EXPECT_EQ(o.height, 240);
  EXPECT_EQ(o.format, "BGR888");
  EXPECT_EQ(o.buffers, 6);
  EXPECT_EQ(o.reopen_ms, 100);
  EXPECT_EQ(o.stall_ms, 500);
}

TEST(LibcameraOptions, EmptyIdMeansTheFirstCameraWithDefaults) {
  const LibcameraOptions o = parse_libcamera_options("");
  EXPECT_TRUE(o.camera_id.empty());
  EXPECT_EQ(o.width, 640);
  EXPECT_EQ(o.height, 480);
  EXPECT_TRUE(o.format.empty());
  EXPECT_EQ(o.buffers, 4);
  EXPECT_EQ(parse_libcamera_options("?size=1280x720").camera_id, "");
  // A UVC camera's id has ':' in it; the options still follow the '?'.
  EXPECT_EQ(parse_libcamera_options(R"(\_SB_.PCI0-1:1.0-046d:0825?buffers=3)").camera_id,
            R"(\_SB_.PCI0-1:1.0-046d:0825)");
}

TEST(LibcameraOptions, RejectsBadValuesNamingTheKey) {
  const std::pair<const char*, const char*> cases[] = {
      {"?size=640", "'size'"},       {"?size=0x480", "'size'"},   {"?size=64x48x2", "'size'"},
      {"?buffers=1", "'buffers'"},   {"?buffers=x", "'buffers'"}, {"?reopen_ms=5", "'reopen_ms'"},
      {"?stall_ms=0", "'stall_ms'"}, {"?format=", "'format'"},    {"?colour=1", "'colour'"},
      {"cam?fps=30", "'fps'"},  // libcamera takes the rate from the pipeline; not an option here
  };
  for (const auto& [spec, key] : cases) {
    try {
      parse_libcamera_options(spec);
      ADD_FAILURE() << spec << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << spec << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("libcamera"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace probeless::libcam
