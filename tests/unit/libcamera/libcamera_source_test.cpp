// The libcamera source's parts that need no camera: a machine without one (this host) gives
// "no device" with the reason, not a crash; read() keeps its timeout; the rig factory's
// libcamera specs; the format map; the `probeless devices` section. Streaming, controls and
// unplug run against vimc in a VM (tests/vm/libcamera_vimc_test.cpp).
#include <gtest/gtest.h>
#include <libcamera/formats.h>

#include <chrono>
#include <sstream>

#include "app/cli/devices_libcamera.hpp"
#include "drivers/libcamera/libcamera_fisheye_source.hpp"
#include "drivers/libcamera/libcamera_format_map.hpp"
#include "drivers/libcamera/libcamera_runtime.hpp"
#include "drivers/rig_factory.hpp"

namespace probeless::libcam {
namespace {

using namespace std::chrono_literals;

TEST(LibcameraSource, AbsentCameraIsNoDeviceNamingItAndReadKeepsItsTimeout) {
  LibcameraOptions o;
  o.camera_id = "probeless-no-such-camera";
  o.reopen_ms = 1000;
  LibcameraFisheyeSource source(o);
  EXPECT_EQ(source.state(), SourceState::NoDevice);
  EXPECT_NE(source.last_error().find("probeless-no-such-camera"), std::string::npos)
      << source.last_error();
  EXPECT_EQ(source.stream_info(), nullptr);
  EXPECT_EQ(source.name(), "libcamera:probeless-no-such-camera");
  FisheyeFrame frame;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(source.read(frame, 50ms), ReadResult::Error);
  const auto took = std::chrono::steady_clock::now() - t0;
  EXPECT_GE(took, 40ms);   // waited for the next look, did not spin
  EXPECT_LT(took, 300ms);  // and not past the timeout
  EXPECT_EQ(source.state(), SourceState::NoDevice);
}

TEST(LibcameraSource, FirstCameraWithNoneIsNoDevice) {
  if (!list_libcamera_cameras().empty()) GTEST_SKIP() << "this machine has a libcamera camera";
  LibcameraFisheyeSource source(LibcameraOptions{});
  EXPECT_EQ(source.state(), SourceState::NoDevice);
  EXPECT_EQ(source.last_error(), "libcamera finds no camera");
  source.set_next_exposure({});  // harmless without a camera
}

// Two sources and the listing share one CameraManager (libcamera aborts on a second one).
TEST(LibcameraSource, SourcesAndListingShareTheManager) {
  LibcameraOptions o;
  o.camera_id = "a";
  LibcameraFisheyeSource a(o);
  o.camera_id = "b";
  LibcameraFisheyeSource b(o);
  EXPECT_NO_THROW(list_libcamera_cameras());
  EXPECT_EQ(shared_camera_manager(), shared_camera_manager());
}

TEST(LibcameraRigFactory, SpecPairsTheSimRgbdWithTheCameraFisheye) {
  Rig rig = open_rig("libcamera:probeless-no-such-camera?size=320x240");
  ASSERT_TRUE(rig.rgbd && rig.fisheye);
  EXPECT_EQ(rig.rgbd->name(), "sim");
  EXPECT_EQ(rig.fisheye->name(), "libcamera:probeless-no-such-camera");
  EXPECT_EQ(rig.fisheye->state(), SourceState::NoDevice);
  Rig combined = open_rig("sim+libcamera:probeless-no-such-camera");
  ASSERT_TRUE(combined.fisheye);
  EXPECT_EQ(combined.fisheye->state(), SourceState::NoDevice);
  try {
    open_rig("libcamera:x?buffers=99");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'buffers'"), std::string::npos) << e.what();
  }
  EXPECT_NE(rig_spec_help().find("libcamera:"), std::string::npos);
}

TEST(LibcameraFormatMap, DrmNamesMapToTheConversionsBayerFirst) {
  namespace f = libcamera::formats;
  // libcamera's BGR888 is DRM's: bytes R, G, B in memory, i.e. V4L2's RGB24.
  EXPECT_EQ(pixel_layout(f::BGR888)->layout, v4l2::PixelLayout::RGB24);
  EXPECT_EQ(pixel_layout(f::RGB888)->layout, v4l2::PixelLayout::BGR24);
  EXPECT_EQ(pixel_layout(f::SGRBG10)->bits, 10);
  EXPECT_EQ(pixel_layout(f::SGRBG10)->bayer, v4l2::BayerOrder::GRBG);
  EXPECT_FALSE(pixel_layout(f::SRGGB10_CSI2P));  // packed: not converted
  EXPECT_FALSE(pixel_layout(f::NV12));
  EXPECT_LT(format_rank(f::SRGGB12), format_rank(f::SRGGB8));
  EXPECT_LT(format_rank(f::SRGGB8), format_rank(f::BGR888));
  EXPECT_LT(format_rank(f::BGR888), format_rank(f::YUYV));
  EXPECT_EQ(format_rank(f::NV12), -1);
}

TEST(LibcameraDevices, SectionSaysWhatItFound) {
  std::ostringstream out;
  cli::print_libcamera_cameras(out);
  const std::string text = out.str();
  EXPECT_EQ(text.rfind("libcamera cameras\n", 0), 0u) << text;
  if (list_libcamera_cameras().empty())
    EXPECT_NE(text.find("no camera: libcamera found none"), std::string::npos) << text;
  else
    EXPECT_NE(text.find("ExposureTime: "), std::string::npos) << text;
}

}  // namespace
}  // namespace probeless::libcam
