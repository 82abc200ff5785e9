// The V4L2 source's parts that need no device: the spec, the "no device" state and its
// timing, the rig factory's v4l2 specs. The streaming tests run against vivid in a VM
// (tests/vm/v4l2_vivid_test.cpp).
#include <gtest/gtest.h>

#include <chrono>

#include "drivers/rig_factory.hpp"
#include "drivers/v4l2/v4l2_fisheye_source.hpp"
#include "drivers/v4l2/v4l2_options.hpp"

namespace probeless::v4l2 {
namespace {

using namespace std::chrono_literals;

TEST(V4l2Options, ParsesDeviceSizeRateAndTheRest) {
  const V4l2Options o = parse_v4l2_options(
      "/dev/"
      "video3?size=320x180&fps=15,format=YUYV&buffers=6&latency=0&unity_gain=64&reopen_ms=100");
  EXPECT_EQ(o.device, "/dev/video3");
  EXPECT_EQ(o.width, 320);
  EXPECT_EQ(o.height, 180);
  EXPECT_DOUBLE_EQ(o.fps, 15);
  EXPECT_EQ(o.format, "YUYV");
  EXPECT_EQ(o.buffers, 6);
  EXPECT_EQ(o.latency_frames, 0);
  EXPECT_EQ(o.unity_gain, 64);
  EXPECT_EQ(o.reopen_ms, 100);
  EXPECT_EQ(parse_v4l2_options("vivid").device, "vivid");  // a card name
}

TEST(V4l2Options, RejectsBadValuesNamingTheKey) {
  for (const char* spec :
       {"", "?size=640", "/dev/video0?size=0x480", "/dev/video0?fps=-1", "/dev/video0?format=YU",
        "/dev/video0?buffers=1", "/dev/video0?colour=1"}) {
    EXPECT_THROW(parse_v4l2_options(spec), std::invalid_argument) << spec;
  }
  try {
    parse_v4l2_options("/dev/video0?fps=abc");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("fps"), std::string::npos);
  }
}

// A device that is not there is a state, not an exception: read() says Error within its
// timeout, state() says no device, last_error() names the node.
TEST(V4l2Source, MissingDeviceIsNoDeviceAndReadKeepsItsTimeout) {
  V4l2Options o;
  o.device = "/dev/v4l2-test-no-such-node";
  o.reopen_ms = 1000;
  V4l2FisheyeSource source(o);
  EXPECT_EQ(source.state(), SourceState::NoDevice);
  EXPECT_NE(source.last_error().find("v4l2-test-no-such-node"), std::string::npos);
  EXPECT_EQ(source.capture_info(), nullptr);
  FisheyeFrame frame;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(source.read(frame, 50ms), ReadResult::Error);
  const auto took = std::chrono::steady_clock::now() - t0;
  EXPECT_GE(took, 40ms);   // waited for the next look, did not spin
  EXPECT_LT(took, 300ms);  // and not past the timeout
  EXPECT_EQ(source.state(), SourceState::NoDevice);
}

TEST(V4l2Source, CardNameThatNoDeviceHasIsNoDevice) {
  V4l2Options o;
  o.device = "probeless-no-such-card";
  V4l2FisheyeSource source(o);
  EXPECT_EQ(source.state(), SourceState::NoDevice);
  EXPECT_NE(source.last_error().find("probeless-no-such-card"), std::string::npos);
}

TEST(RigFactory, V4l2SpecPairsTheSimRgbdWithTheCameraFisheye) {
  Rig rig = open_rig("v4l2:/dev/v4l2-test-no-such-node?size=320x180&fps=15");
  ASSERT_TRUE(rig.rgbd);
  ASSERT_TRUE(rig.fisheye);
  EXPECT_EQ(rig.rgbd->name(), "sim");
  EXPECT_EQ(rig.fisheye->name(), "v4l2:/dev/v4l2-test-no-such-node");
  EXPECT_EQ(rig.fisheye->state(), SourceState::NoDevice);

  Rig combined = open_rig("sim:realtime=0+v4l2:/dev/v4l2-test-no-such-node");
  EXPECT_EQ(combined.fisheye->name(), "v4l2:/dev/v4l2-test-no-such-node");

  EXPECT_THROW(open_rig("v4l2:/dev/video0?bogus=1"), std::invalid_argument);
  EXPECT_THROW(open_rig("sim+nothing:x"), std::invalid_argument);
  EXPECT_NE(rig_spec_help().find("v4l2:"), std::string::npos);
}

}  // namespace
}  // namespace probeless::v4l2
