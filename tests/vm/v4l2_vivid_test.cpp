// The V4L2 fisheye source against a real kernel driver, vivid (issue #7 "Tests on real
// kernel drivers"). Runs inside the VM of tests/vm/run_in_vm.sh after `modprobe vivid`
// (check_vivid.sh); on a machine without vivid it skips, unless PROBELESS_REQUIRE_VIVID=1
// (set in the VM) makes that a failure.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "drivers/replay/recording_writer.hpp"
#include "drivers/rig_factory.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "drivers/v4l2/v4l2_camera.hpp"
#include "drivers/v4l2/v4l2_fisheye_source.hpp"

namespace probeless::v4l2 {
namespace {

using namespace std::chrono_literals;
const std::filesystem::path kDriver = "/sys/bus/platform/drivers/vivid";

// vivid's webcam input offers every rate up to 60 fps only at its smallest size.
V4l2Options vivid(double fps = 30, const std::string& format = {}) {
  V4l2Options o;
  o.device = "vivid";  // by card name: the node may be renumbered after a rebind
  o.width = 320;
  o.height = 180;
  o.fps = fps;
  o.format = format;
  o.latency_frames = 0;  // no sensor behind vivid: a control applies to the next frame
  o.reopen_ms = 100;
  return o;
}

class Vivid : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kDriver)) {
      const char* require = std::getenv("PROBELESS_REQUIRE_VIVID");
      if (require != nullptr && std::string(require) == "1") FAIL() << "vivid is not loaded";
      GTEST_SKIP() << "vivid is not loaded (tests/vm/check_vivid.sh runs this in a VM)";
    }
  }
};

// Reads until `n` frames arrived, each within `each` (a lost frame is a failure).
std::vector<FisheyeFrame> read_frames(V4l2FisheyeSource& s, int n, std::chrono::milliseconds each) {
  std::vector<FisheyeFrame> frames;
  auto deadline = std::chrono::steady_clock::now() + each * (n + 5);
  while (static_cast<int>(frames.size()) < n && std::chrono::steady_clock::now() < deadline) {
    FisheyeFrame f;
    if (s.read(f, each) == ReadResult::Frame) frames.push_back(std::move(f));
  }
  return frames;
}

TEST_F(Vivid, StreamsRawBayerFramesWithDriverTimestampsAtTheNegotiatedSize) {
  V4l2FisheyeSource source(vivid());
  ASSERT_NE(source.capture_info(), nullptr) << source.last_error();
  const CaptureInfo& info = *source.capture_info();
  // vivid offers 12-bit Bayer: the source must prefer linear raw over RGB/YUYV.
  EXPECT_EQ(info.pixel.layout, PixelLayout::Bayer16) << info.fourcc;
  EXPECT_EQ(info.pixel.bits, 12);
  const auto frames = read_frames(source, 20, 500ms);
  ASSERT_EQ(frames.size(), 20u) << source.last_error();
  EXPECT_EQ(source.state(), SourceState::Streaming);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].raw.width(), 320);
    EXPECT_EQ(frames[i].raw.height(), 180);
    EXPECT_EQ(frames[i].bit_depth, 12);
    if (i > 0) {
      EXPECT_GT(frames[i].timestamp_ns, frames[i - 1].timestamp_ns);
      EXPECT_EQ(frames[i].sequence, frames[i - 1].sequence + 1);
    }
  }
  // CLOCK_MONOTONIC, as every frame in the project: the last one is from the last second.
  EXPECT_LT(std::llabs(monotonic_now_ns() - frames.back().timestamp_ns), 1'000'000'000LL);
  // vivid's test pattern has colour bars: the frame is not flat.
  const auto [lo, hi] =
      std::minmax_element(frames.back().raw.elements().begin(), frames.back().raw.elements().end());
  EXPECT_LT(*lo + 1000, *hi);
}

TEST_F(Vivid, GammaCodedFormatsOnRequest) {
  for (const char* format : {"YUYV", "RGB3"}) {
    V4l2FisheyeSource source(vivid(30, format));
    ASSERT_NE(source.capture_info(), nullptr) << format << ": " << source.last_error();
    EXPECT_EQ(source.capture_info()->fourcc, format);
    const auto frames = read_frames(source, 3, 500ms);
    ASSERT_EQ(frames.size(), 3u) << format;
    EXPECT_EQ(frames.back().bit_depth, 12);
    const auto [lo, hi] = std::minmax_element(frames.back().raw.elements().begin(),
                                              frames.back().raw.elements().end());
    EXPECT_LT(*lo + 1000, *hi) << format;
  }
}

TEST_F(Vivid, FrameIntervalIsNegotiatedAndKept) {
  V4l2FisheyeSource source(vivid(15));
  ASSERT_NE(source.capture_info(), nullptr) << source.last_error();
  EXPECT_TRUE(source.capture_info()->fps_from_device);
  EXPECT_NEAR(source.capture_info()->fps, 15.0, 1e-6);
  // The period from the driver's timestamps over its own sequence numbers: vivid skips the
  // ticks its thread missed on a loaded host (TCG beside a busy machine) and counts them, and
  // one late frame shortens the next interval, so single intervals say little; a second's
  // span does. 30 or 7.5 fps would be 50 % off.
  std::vector<std::pair<TimestampNs, std::uint32_t>> stamps;
  while (stamps.size() < 16) {
    FisheyeFrame f;
    const auto r = source.read(f, 500ms);
    ASSERT_NE(r, ReadResult::Error) << source.last_error();
    if (r == ReadResult::Frame) stamps.emplace_back(f.timestamp_ns, source.driver_sequence());
  }
  const auto frames = stamps.back().second - stamps.front().second;
  ASSERT_GE(frames, 15u);
  const double period_s = (stamps.back().first - stamps.front().first) / 1e9 / frames;
  EXPECT_NEAR(period_s, 1.0 / 15, 0.1 / 15);
  std::printf("[ vivid    ] 15 fps: period %.2f ms over %u driver frames (%zu read)\n",
              period_s * 1e3, frames, stamps.size());
}

std::int32_t read_control(const std::string& path, std::uint32_t id) {
  const int fd = ::open(path.c_str(), O_RDWR);
  v4l2_control c{id, -1};
  const int r = ::ioctl(fd, VIDIOC_G_CTRL, &c);
  ::close(fd);
  return r == 0 ? c.value : -1;
}

// vivid has gain (0..255, default 100 = unity here) and autogain, no exposure time: the
// source turns autogain off, sets gain, and stamps frames with what it read back.
TEST_F(Vivid, GainIsSetReadBackAndStampedOnFrames) {
  V4l2FisheyeSource source(vivid());
  ASSERT_NE(source.capture_info(), nullptr) << source.last_error();
  const CaptureInfo info = *source.capture_info();
  ASSERT_TRUE(info.gain.present);
  EXPECT_FALSE(info.exposure.present);
  ExposureStamp want;
  want.exposure = {0.005, gain_db_from_linear(2.0)};
  want.level = BracketLevel::High;
  want.cycle_position = 2;
  // Frames already filled when the controls changed keep the old stamp; within a few frames
  // (the buffers in flight) the new one must show, and nothing else in between.
  auto read_until_gain = [&](double gain_db) {
    for (int i = 0; i < 12; ++i) {
      const auto f = read_frames(source, 1, 500ms);
      if (f.empty()) break;
      if (std::abs(f[0].exposure.exposure.gain_db - gain_db) < 1e-9) return f[0].exposure;
    }
    ADD_FAILURE() << "no frame stamped " << gain_db << " dB";
    return ExposureStamp{};
  };
  source.set_next_exposure(want);
  const ExposureStamp got = read_until_gain(20 * std::log10(2.0));
  EXPECT_EQ(read_control(info.path, V4L2_CID_GAIN), 200);
  EXPECT_EQ(read_control(info.path, V4L2_CID_AUTOGAIN), 0);
  EXPECT_DOUBLE_EQ(got.exposure.time_s, 0.005);  // no exposure control: as requested
  EXPECT_EQ(got.level, BracketLevel::High);
  // Past the control's range: clamped to 255, and the stamp says so.
  want.exposure.gain_db = 20;
  source.set_next_exposure(want);
  read_until_gain(20 * std::log10(2.55));
  EXPECT_EQ(read_control(info.path, V4L2_CID_GAIN), 255);
}

std::string vivid_device_name() {
  for (const auto& e : std::filesystem::directory_iterator(kDriver))
    if (e.is_symlink() && e.path().filename().string().starts_with("vivid"))
      return e.path().filename();
  return {};
}

void write_sysfs(const std::filesystem::path& file, const std::string& value) {
  std::ofstream out(file);
  out << value << std::flush;
  ASSERT_TRUE(out.good()) << "writing " << value << " to " << file;
}

// The bar: unplug -> "no device" within one frame period, frames back within 2 s
// of replug. Unbinding vivid's platform device removes /dev/videoN under the open file.
// Asserted in reads, not wall time (issue #20: the VM runs under TCG beside loaded hosts,
// where 49 ms once passed between the unbind returning and the next read's verdict): the
// first read that starts after the unbind has returned must say no device, and frames must
// come back after the rebind while the source keeps looking every 100 ms. The times are
// printed; docs/drivers.md quotes them.
TEST_F(Vivid, UnbindIsNoDeviceWithinAFramePeriodAndRebindStreamsWithinTwoSeconds) {
  const std::string dev = vivid_device_name();
  ASSERT_FALSE(dev.empty());
  V4l2FisheyeSource source(vivid(30));
  ASSERT_EQ(read_frames(source, 5, 500ms).size(), 5u) << source.last_error();
  const auto period = std::chrono::nanoseconds(1'000'000'000 / 30);

  // Unbind from another thread: the kernel may wait for our file to close.
  std::atomic<std::int64_t> unbound_ns{0};
  std::thread unbind([&] {
    write_sysfs(kDriver / "unbind", dev);
    unbound_ns = monotonic_now_ns();
  });
  std::int64_t no_device_ns = 0;
  int reads_after_unbind = 0;  // reads begun once the unbind had returned
  const auto give_up = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < give_up) {
    FisheyeFrame f;
    if (unbound_ns.load() != 0) ++reads_after_unbind;
    source.read(f, std::chrono::duration_cast<std::chrono::milliseconds>(period));
    if (source.state() == SourceState::NoDevice) {
      no_device_ns = monotonic_now_ns();
      break;
    }
  }
  unbind.join();
  ASSERT_NE(no_device_ns, 0) << "never reported no device";
  EXPECT_LE(reads_after_unbind, 1) << "reads after the unbind before no device";
  std::printf("[ vivid    ] no device %.1f ms after the unbind returned (%d reads after it)\n",
              (no_device_ns - unbound_ns.load()) / 1e6, reads_after_unbind);
  FisheyeFrame f;
  EXPECT_NE(source.read(f, 50ms), ReadResult::Frame);  // still gone

  write_sysfs(kDriver / "bind", dev);
  const std::int64_t bound_ns = monotonic_now_ns();
  std::int64_t frame_ns = 0;
  while (monotonic_now_ns() - bound_ns < 30'000'000'000LL) {
    if (source.read(f, 100ms) == ReadResult::Frame) {
      frame_ns = monotonic_now_ns();
      break;
    }
  }
  ASSERT_NE(frame_ns, 0) << "no frame within 30 s of the rebind: " << source.last_error();
  std::printf("[ vivid    ] first frame %.1f ms after the bind\n", (frame_ns - bound_ns) / 1e6);
  EXPECT_EQ(source.state(), SourceState::Streaming);
  EXPECT_EQ(f.raw.width(), 320);
}

// The boards' rig (board/*/board.toml, docs/boards.md): an OpenNI2 RGB-D sensor and a V4L2
// fisheye in one spec, through the rig factory, with the unit's calibration file. OpenNI2's
// Dummy device stands in for the sensor (the guest runs the host's libOpenNI2 and drivers).
TEST_F(Vivid, OpenNi2AndV4l2CombineIntoOneRig) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "probeless-combined-rig";
  fs::remove_all(dir);
  {
    // A calibration file as a bring-up writes one; the sim's geometry will do.
    replay::RecordingWriter writer(dir, sim::make_sim_rig(sim::parse_sim_options("")).calibration);
  }
  const std::string spec =
      "openni2:Dummy?size=320x240&hotplug=0+v4l2:vivid?size=320x180&fps=30&latency=0&calibration=" +
      (dir / "calibration.toml").string();
  Rig rig;
  try {
    rig = open_rig(spec);
  } catch (const std::exception& e) {
    FAIL() << spec << ": " << e.what();
  }
  ASSERT_TRUE(rig.rgbd && rig.fisheye);
  ASSERT_TRUE(rig.calibration.fisheye) << "the calibration file's fisheye model";
  int rgbd = 0, fisheye = 0;
  const auto give_up = std::chrono::steady_clock::now() + 20s;
  while ((rgbd < 5 || fisheye < 5) && std::chrono::steady_clock::now() < give_up) {
    RgbdFrame r;
    if (rgbd < 5 && rig.rgbd->read(r, 200ms) == ReadResult::Frame) {
      EXPECT_EQ(r.colour.width(), 320);
      EXPECT_EQ(r.depth.width(), 320);
      ++rgbd;
    }
    FisheyeFrame f;
    if (fisheye < 5 && rig.fisheye->read(f, 200ms) == ReadResult::Frame) {
      EXPECT_EQ(f.raw.width(), 320);
      ++fisheye;
    }
  }
  EXPECT_EQ(rgbd, 5) << rig.rgbd->last_error();
  EXPECT_EQ(fisheye, 5) << rig.fisheye->last_error();
  std::printf("[ vivid    ] %s: %d RGB-D + %d fisheye frames\n", rig.rgbd->name().c_str(), rgbd,
              fisheye);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace probeless::v4l2
