// The libcamera fisheye source against a real kernel driver and libcamera's own pipeline
// handler: vimc (issue #7 "Tests on real kernel drivers"). Runs inside the VM of
// tests/vm/run_in_vm.sh after check_vimc.sh loaded vimc and started systemd-udevd (libcamera
// finds cameras and their removal through udev); elsewhere it skips, unless
// PROBELESS_REQUIRE_VIMC=1 (set in the VM) makes that a failure.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <vector>

#include "drivers/libcamera/libcamera_camera.hpp"
#include "drivers/libcamera/libcamera_fisheye_source.hpp"
#include "drivers/libcamera/libcamera_runtime.hpp"

namespace probeless::libcam {
namespace {

using namespace std::chrono_literals;
const std::filesystem::path kDriver = "/sys/bus/platform/drivers/vimc";
const std::string kCamera = "platform/vimc.0 Sensor B";  // the one vimc's pipeline exposes

// libcamera 0.0.3's vimc pipeline rounds widths down to a multiple of 12 (640 gives 636):
// 480x360 is one it gives exactly, and small enough for TCG.
LibcameraOptions vimc(int width = 480, int height = 360) {
  LibcameraOptions o;
  o.camera_id = kCamera;
  o.width = width;
  o.height = height;
  o.reopen_ms = 100;
  return o;
}

class Vimc : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kDriver)) {
      const char* require = std::getenv("PROBELESS_REQUIRE_VIMC");
      if (require != nullptr && std::string(require) == "1") FAIL() << "vimc is not loaded";
      GTEST_SKIP() << "vimc is not loaded (tests/vm/check_vimc.sh runs this in a VM)";
    }
  }
};

// The bracket cycle L, M, H, M as the sequencer stamps it (drivers/bracket).
ExposureStamp bracket(std::uint64_t n) {
  static constexpr std::array<BracketLevel, 4> kLevels{BracketLevel::Low, BracketLevel::Medium,
                                                       BracketLevel::High, BracketLevel::Medium};
  static constexpr std::array<double, 4> kTimes{0.002, 0.008, 0.016, 0.008};
  static constexpr std::array<double, 4> kGains{0.0, 0.0, 6.0, 0.0};
  ExposureStamp s;
  const auto p = static_cast<std::uint32_t>(n % 4);
  s.exposure = {kTimes[p], kGains[p]};
  s.level = kLevels[p];
  s.cycle_position = p;
  s.cycle = n / 4;
  return s;
}

// Reads `n` frames, asking for the next bracket exposure before each read, as the capture
// thread does. Stops early when a read gives no frame for `each`.
std::vector<FisheyeFrame> read_bracketed(LibcameraFisheyeSource& s, int n,
                                         std::chrono::milliseconds each) {
  std::vector<FisheyeFrame> frames;
  std::uint64_t asked = 0;
  const auto deadline = std::chrono::steady_clock::now() + each * (n + 5);
  while (static_cast<int>(frames.size()) < n && std::chrono::steady_clock::now() < deadline) {
    s.set_next_exposure(bracket(asked++));
    FisheyeFrame f;
    if (s.read(f, each) == ReadResult::Frame) frames.push_back(std::move(f));
  }
  return frames;
}

TEST_F(Vimc, ListsTheCameraWithItsControls) {
  const auto cameras = list_libcamera_cameras();
  ASSERT_EQ(cameras.size(), 1u);
  EXPECT_EQ(cameras[0].id, kCamera);
  std::string controls;
  for (const auto& c : cameras[0].controls) controls += c + "; ";
  std::printf("[ vimc     ] controls: %s ExposureTime %s, AnalogueGain %s\n", controls.c_str(),
              cameras[0].exposure_time ? "yes" : "no", cameras[0].analogue_gain ? "yes" : "no");
}

// 30+ frames with the bracket's exposures asked per request: in order, SensorTimestamps
// strictly increasing on CLOCK_MONOTONIC, converted to 480x360 RGB16 that is not flat, each
// stamped with its own request's exposure and bracket place (what the request asked, where
// vimc offers no such control; what the metadata says was applied where it does).
TEST_F(Vimc, StreamsThirtyBracketedFramesWithIncreasingSensorTimestamps) {
  LibcameraFisheyeSource source(vimc());
  ASSERT_EQ(source.state(), SourceState::NoSignal) << source.last_error();
  const StreamInfo* info = source.stream_info();
  ASSERT_NE(info, nullptr);
  std::printf("[ vimc     ] %s %dx%d, ExposureTime %s, AnalogueGain %s\n", info->format.c_str(),
              info->width, info->height, info->exposure_time ? "per request" : "not offered",
              info->analogue_gain ? "per request" : "not offered");
  const auto t0 = std::chrono::steady_clock::now();
  const auto frames = read_bracketed(source, 40, 2000ms);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_GE(frames.size(), 30u) << source.last_error();
  EXPECT_EQ(source.state(), SourceState::Streaming);
  std::set<std::uint32_t> positions;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const FisheyeFrame& f = frames[i];
    EXPECT_EQ(f.sequence, i);
    EXPECT_EQ(f.raw.width(), 480);
    EXPECT_EQ(f.raw.height(), 360);
    EXPECT_EQ(f.bit_depth, 12);  // BGR888, linearised into 12 bit
    if (i > 0) {
      EXPECT_GT(f.timestamp_ns, frames[i - 1].timestamp_ns) << "frame " << i;
    }
    EXPECT_LE(f.timestamp_ns, monotonic_now_ns());  // CLOCK_MONOTONIC, not wall time
    // The first requests were queued at start, before any set_next_exposure: the default
    // stamp. After them, the stamp travels with its request: place and exposure together.
    if (f.exposure.level == BracketLevel::Fixed) {
      EXPECT_LT(i, 4u) << "only the requests queued at start are unbracketed";
      continue;
    }
    const ExposureStamp want = bracket(f.exposure.cycle_position);
    EXPECT_EQ(f.exposure.level, want.level) << "frame " << i;
    positions.insert(f.exposure.cycle_position);
    if (!info->exposure_time) {
      EXPECT_DOUBLE_EQ(f.exposure.exposure.time_s, want.exposure.time_s) << "frame " << i;
    }
    if (!info->analogue_gain) {
      EXPECT_DOUBLE_EQ(f.exposure.exposure.gain_db, want.exposure.gain_db) << "frame " << i;
    }
  }
  EXPECT_EQ(positions.size(), 4u);  // the whole cycle went through the requests
  const ImageRGB16& last = frames.back().raw;
  const std::uint16_t* px = last.data();
  const auto [lo, hi] = std::minmax_element(px, px + std::size_t{480} * 360 * 3);
  EXPECT_LT(*lo + 100, *hi) << "a flat frame";  // vimc's sensor draws a test pattern
  const double span_s = (frames.back().timestamp_ns - frames.front().timestamp_ns) / 1e9;
  std::printf(
      "[ vimc     ] %zu frames in %.2f s (%.1f fps by SensorTimestamp), pipeline "
      "sequence %u\n",
      frames.size(), took, (frames.size() - 1) / span_s, source.pipeline_sequence());
}

// The values a request's metadata reports as applied, straight from the camera: vimc's
// pipeline reports none of ExposureTime/AnalogueGain (it has neither control), so frames keep
// what was asked; this test says so rather than assuming it.
TEST_F(Vimc, MetadataReportsWhatThePipelineApplied) {
  LibcameraCamera camera(shared_camera_manager(), vimc(), bracket(0));
  int frames = 0;
  bool exposure = false, gain = false;
  for (int i = 0; i < 50 && frames < 8; ++i) {
    camera.next_frame(2000ms, bracket(static_cast<std::uint64_t>(i)), [&](const CompletedFrame& c) {
      ++frames;
      exposure = exposure || c.exposure_us.has_value();
      gain = gain || c.analogue_gain.has_value();
      EXPECT_GT(c.timestamp_ns, 0);
    });
  }
  ASSERT_EQ(frames, 8);
  EXPECT_EQ(exposure, camera.info().exposure_time);
  EXPECT_EQ(gain, camera.info().analogue_gain);
  std::printf("[ vimc     ] metadata: ExposureTime %s, AnalogueGain %s\n",
              exposure ? "reported" : "absent", gain ? "reported" : "absent");
}

TEST_F(Vimc, FirstCameraAndBadSizeOrFormat) {
  LibcameraOptions first = vimc(240, 180);
  first.camera_id.clear();
  {
    LibcameraFisheyeSource source(first);
    ASSERT_NE(source.stream_info(), nullptr) << source.last_error();
    EXPECT_EQ(source.stream_info()->camera_id, kCamera);
    LibcameraFisheyeSource second(vimc());  // acquired by the first: no device, saying why
    EXPECT_EQ(second.state(), SourceState::NoDevice);
    EXPECT_NE(second.last_error().find("cannot be acquired"), std::string::npos)
        << second.last_error();
  }
  EXPECT_THROW(LibcameraFisheyeSource(vimc(8000, 6000)), ConfigError);  // past 4096x2160
  try {  // adjusted by the pipeline: an error naming what it would give, not a silent change
    LibcameraFisheyeSource s(vimc(640, 480));
    FAIL() << "640x480 accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("636x480"), std::string::npos) << e.what();
  }
  LibcameraOptions yuyv = vimc();
  yuyv.format = "YUYV";  // convertible, but vimc's pipeline offers only BGR888/RGB888
  try {
    LibcameraFisheyeSource s(yuyv);
    FAIL() << "YUYV accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("BGR888"), std::string::npos) << e.what();
  }
}

void write_sysfs(const std::filesystem::path& file, const std::string& value) {
  std::ofstream out(file);
  out << value << std::flush;
  ASSERT_TRUE(out.good()) << "writing " << value << " to " << file;
}

// Unbinding vimc's platform device removes its media and video nodes under the open camera.
// libcamera 0.0.3 sees the media device go (udev) but emits Camera::disconnected only for
// UVC, so the source notices its video nodes vanish and says "no device". No rebind: 0.0.3
// still lists the old camera and aborts when the new one registers the same id
// (docs/drivers.md "libcamera fisheye").
TEST_F(Vimc, UnbindIsNoDevice) {
  LibcameraFisheyeSource source(vimc());
  ASSERT_EQ(read_bracketed(source, 5, 2000ms).size(), 5u) << source.last_error();
  write_sysfs(kDriver / "unbind", "vimc.0");
  const std::int64_t unbound_ns = monotonic_now_ns();
  std::int64_t no_device_ns = 0;
  while (monotonic_now_ns() - unbound_ns < 10'000'000'000LL) {
    FisheyeFrame f;
    source.read(f, 50ms);
    if (source.state() == SourceState::NoDevice) {
      no_device_ns = monotonic_now_ns();
      break;
    }
  }
  ASSERT_NE(no_device_ns, 0) << "never reported no device; state " << to_string(source.state());
  std::printf("[ vimc     ] no device %.1f ms after the unbind (%s)\n",
              (no_device_ns - unbound_ns) / 1e6, source.last_error().c_str());
  EXPECT_LT(no_device_ns - unbound_ns, 2'000'000'000LL);
  EXPECT_NE(source.last_error().find("gone"), std::string::npos) << source.last_error();
  FisheyeFrame f;
  EXPECT_EQ(source.read(f, 300ms), ReadResult::Error);  // looked again: still gone, says so
  EXPECT_EQ(source.state(), SourceState::NoDevice);
  EXPECT_NE(source.last_error().find("gone"), std::string::npos) << source.last_error();
}

}  // namespace
}  // namespace probeless::libcam
