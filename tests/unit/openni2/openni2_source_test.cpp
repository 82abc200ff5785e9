// The OpenNI2 RGB-D source through the real OpenNI2 library (libopenni2-0): its Dummy device
// live, and .oni recordings made from it with openni::Recorder played back through libOniFile.
// Each test skips with the reason when a piece of OpenNI2 is missing.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "drivers/openni2/openni2_camera.hpp"
#include "drivers/openni2/openni2_options.hpp"
#include "drivers/openni2/openni2_rgbd_source.hpp"
#include "drivers/rig_factory.hpp"
#include "support/subprocess.hpp"

namespace probeless::openni2 {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

constexpr const char* kDummy = "Dummy?size=320x240&hotplug=0&stall_ms=300";

fs::path scratch_dir() {
  const fs::path dir =
      fs::temp_directory_path() / ("probeless-openni2-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

class OniPlayback : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = scratch_dir();
    file_ = dir_ / "dummy.oni";
    // Up to three tries: OpenNI's Recorder with the Dummy driver sometimes deadlocks.
    for (int attempt = 0; attempt < 3; ++attempt) {
      probeless::testing::Subprocess recorder({PROBELESS_OPENNI2_RECORDER, file_.string(), "12"},
                                              {}, true);
      const auto status = recorder.wait(15s);
      if (status == 0) {
        skip_.clear();
        return;
      }
      skip_ = "recording the Dummy device failed: " +
              (status ? "exit " + std::to_string(*status) : std::string("hung")) + ": " +
              recorder.output();
    }
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  void SetUp() override {
    if (!skip_.empty()) GTEST_SKIP() << skip_;
  }
  static Openni2Options options(const std::string& query = "") {
    return parse_openni2_options(file_.string() + query);
  }
  static inline fs::path dir_, file_;
  static inline std::string skip_;
};

// The RGB-D pairs a recording holds: OpenNI's recorder rebases each stream's first frame to
// time 0 and may catch one stream a frame earlier or later than the other.
int pairs_in(const Openni2RgbdSource& source) {
  const CameraInfo* info = source.camera_info();
  return info ? std::min(info->colour_frames, info->depth_frames) : 0;
}

struct Played {
  int frames = 0;
  std::chrono::duration<double> took{};
  bool ended = false;
};

Played play(Openni2RgbdSource& source, int max_frames = 1000) {
  Played p;
  RgbdFrame frame;
  TimestampNs last = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (p.frames < max_frames && std::chrono::steady_clock::now() - t0 < 10s) {
    const ReadResult r = source.read(frame, 100ms);
    if (r == ReadResult::EndOfStream) {
      p.ended = true;
      break;
    }
    if (r != ReadResult::Frame) continue;
    EXPECT_EQ(frame.colour.width(), 320);
    EXPECT_EQ(frame.colour.height(), 240);
    EXPECT_EQ(frame.depth.width(), 320);
    EXPECT_EQ(frame.depth.height(), 240);
    EXPECT_GT(frame.timestamp_ns, last) << "frame " << p.frames;
    EXPECT_LE(frame.timestamp_ns, monotonic_now_ns());
    last = frame.timestamp_ns;
    ++p.frames;
  }
  p.took = std::chrono::steady_clock::now() - t0;
  return p;
}

TEST(Openni2Options, ParsesUriModeAndPlayback) {
  const Openni2Options o = parse_openni2_options(
      "1d27/0601@3/2?size=320x240&fps=60&registration=0&sync=0&pair_ms=5&reopen_ms=100&"
      "stall_ms=2000&reset_on_stall=0&hotplug=0&usb_vendors=1d27:2bc5");
  EXPECT_EQ(o.uri, "1d27/0601@3/2");
  EXPECT_FALSE(o.is_file());
  EXPECT_EQ(o.width, 320);
  EXPECT_EQ(o.height, 240);
  EXPECT_EQ(o.fps, 60);
  EXPECT_FALSE(o.registration);
  EXPECT_FALSE(o.sync);
  EXPECT_EQ(o.pair_ms, 5);
  EXPECT_EQ(o.reopen_ms, 100);
  EXPECT_EQ(o.stall_ms, 2000);
  EXPECT_FALSE(o.reset_on_stall);
  EXPECT_FALSE(o.hotplug);
  EXPECT_EQ(o.usb_vendors, (std::vector<std::uint16_t>{0x1d27, 0x2bc5}));
  const Openni2Options f = parse_openni2_options("/data/room.oni?speed=2.5&repeat=1");
  EXPECT_TRUE(f.is_file());
  EXPECT_DOUBLE_EQ(f.speed, 2.5);
  EXPECT_TRUE(f.repeat);
  const Openni2Options d = parse_openni2_options("");
  EXPECT_EQ(d.uri, "");  // the first device
  EXPECT_EQ(d.width, 640);
  EXPECT_EQ(d.height, 480);
  EXPECT_EQ(d.fps, 30);
  EXPECT_TRUE(d.registration);
  EXPECT_TRUE(d.sync);
  EXPECT_EQ(d.usb_vendors, (std::vector<std::uint16_t>{0x1d27, 0x045e, 0x2bc5}));
}

TEST(Openni2Options, RejectsBadValuesNamingTheKey) {
  for (const char* spec :
       {"?size=640", "?size=8x8", "?fps=0", "?fps=29.97", "?sync=yes", "?pair_ms=-1", "?colour=1",
        "?usb_vendors=xyz", "?usb_vendors=12345", "x.oni?speed=-1", "x.oni?repeat=2"}) {
    EXPECT_THROW(parse_openni2_options(spec), std::invalid_argument) << spec;
  }
  try {
    parse_openni2_options("Dummy?speed=2");
    FAIL() << "speed is for recordings";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("recordings"), std::string::npos) << e.what();
  }
}

TEST(Openni2Source, DummyDeviceStreamsPairedFramesWithDepthInMm) {
  Openni2RgbdSource source(parse_openni2_options(kDummy));
  ASSERT_NE(source.camera_info(), nullptr) << source.last_error();
  const CameraInfo& info = *source.camera_info();
  EXPECT_EQ(info.uri, "Dummy");
  EXPECT_EQ(describe(info.colour), "320x240@30 RGB888");
  EXPECT_EQ(describe(info.depth), "320x240@30 DEPTH_1_MM");
  EXPECT_FALSE(info.registered);  // the Dummy device offers no registration
  EXPECT_EQ(source.state(), SourceState::NoSignal);
  RgbdFrame frame;
  int frames = 0;
  TimestampNs last = 0;
  std::vector<TimestampNs> stamps;
  const auto t0 = std::chrono::steady_clock::now();
  while (frames < 15 && std::chrono::steady_clock::now() - t0 < 5s) {
    if (source.read(frame, 100ms) != ReadResult::Frame) continue;
    stamps.push_back(frame.timestamp_ns);
    EXPECT_EQ(frame.sequence, static_cast<std::uint64_t>(frames));
    EXPECT_GT(frame.timestamp_ns, last);
    last = frame.timestamp_ns;
    // The Dummy driver fills its first depth row with 2000 mm and draws a ball elsewhere.
    EXPECT_EQ(frame.depth.at(5, 0), 2000);
    EXPECT_EQ(frame.depth.at(319, 0), 2000);
    ++frames;
  }
  ASSERT_EQ(frames, 15) << source.last_error();
  EXPECT_EQ(source.state(), SourceState::Streaming);
  // Device timestamps keep the device's spacing: a step is a whole number of the Dummy
  // device's 33 ms periods (more than one when the pairing dropped a frame under load). The
  // exception: the clock is anchored on the first frame's arrival, and when a later frame
  // arrives sooner after its device time the anchor is pulled back so that no stamp lies in
  // the future, shortening that one step (seen once in the suite under load: 0.90 periods).
  // That happens once or twice in a run.
  int off_grid = 0;
  for (std::size_t i = 1; i < stamps.size(); ++i) {
    const double step_ms = (stamps[i] - stamps[i - 1]) / 1e6;
    const double periods = step_ms / 33.0;
    EXPECT_GE(periods, 0.5) << "step " << i << ": " << step_ms << " ms";
    if (std::abs(periods - std::round(periods)) > 0.01) ++off_grid;
  }
  EXPECT_LE(off_grid, 2) << "steps off the device's 33 ms grid";
}

// Closing a Dummy device parks its streams instead of destroying them under its driver's
// never-joined threads (openni2_camera.cpp, kParkFor: a segfault of `probeless run` in the VM
// came from that); the device must open again at once, streaming, while the old one waits.
TEST(Openni2Camera, AClosedDummyDeviceIsParkedAndOpensAgainAtOnce) {
  const auto runtime = OpenniRuntime::acquire();
  const auto t0 = std::chrono::steady_clock::now();
  for (int open = 0; open < 3; ++open) {
    Openni2Camera camera(parse_openni2_options(kDummy), runtime);
    ImageRGB8 colour;
    DepthImage depth;
    bool got_colour = false, got_depth = false;
    const auto start = std::chrono::steady_clock::now();
    while (!(got_colour && got_depth) && std::chrono::steady_clock::now() - start < 10s) {
      StreamFrame frame;
      if (!camera.next(100ms, frame, colour, depth)) continue;
      (frame.kind == StreamKind::Colour ? got_colour : got_depth) = true;
    }
    EXPECT_TRUE(got_colour && got_depth) << "opening " << open + 1 << " streamed nothing";
  }
  // Parked entries go only once they are 10 s old, so ours are all still there if the loop
  // took less than that.
  if (std::chrono::steady_clock::now() - t0 < 9s) {
    EXPECT_GE(parked_dummy_devices(), 3u);
  }
}

TEST(Openni2Source, ModeTheDeviceLacksIsAnErrorListingWhatItOffers) {
  try {
    Openni2RgbdSource source(parse_openni2_options("Dummy?hotplug=0"));  // 640x480 by default
    FAIL() << "the Dummy device has no 640x480 mode";
  } catch (const OpenniError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("640x480@30"), std::string::npos) << what;
    EXPECT_NE(what.find("offers: 320x240@30 RGB888"), std::string::npos) << what;
  }
}

TEST(Openni2Source, MissingDeviceIsNoDeviceAndReadKeepsItsTimeout) {
  Openni2RgbdSource source(
      parse_openni2_options("probeless-no-such-device?hotplug=0&reopen_ms=1000"));
  EXPECT_EQ(source.state(), SourceState::NoDevice);
  EXPECT_EQ(source.camera_info(), nullptr);
  EXPECT_NE(source.last_error().find("probeless-no-such-device"), std::string::npos)
      << source.last_error();
  RgbdFrame frame;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(source.read(frame, 50ms), ReadResult::Error);
  const auto took = std::chrono::steady_clock::now() - t0;
  EXPECT_GE(took, 40ms);   // waited for the next look, did not spin
  EXPECT_LT(took, 300ms);  // and not past the timeout
  EXPECT_EQ(source.state(), SourceState::NoDevice);
  // A USB arrival makes the next read look at once instead of at the next reopen_ms.
  source.device_arrived();
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_EQ(source.read(frame, 500ms), ReadResult::Error);
  EXPECT_LT(std::chrono::steady_clock::now() - t1, 300ms);
}

TEST(Openni2Source, FirstDeviceWhenThereIsNoneSaysSo) {
  Openni2RgbdSource source(parse_openni2_options("?hotplug=0"));
  if (const CameraInfo* info = source.camera_info())
    GTEST_SKIP() << "an OpenNI2 device is attached: " << info->uri;
  EXPECT_EQ(source.state(), SourceState::NoDevice);
  EXPECT_NE(source.last_error().find("no devices found"), std::string::npos) << source.last_error();
}

TEST(Openni2Source, MissingOrCorruptRecordingIsAClearError) {
  const fs::path dir = scratch_dir();
  try {
    Openni2RgbdSource source(parse_openni2_options((dir / "absent.oni").string()));
    FAIL();
  } catch (const OpenniError& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  const fs::path junk = dir / "junk.oni";
  std::ofstream(junk) << "this is not an OpenNI recording, just text long enough to read\n";
  try {
    Openni2RgbdSource source(parse_openni2_options(junk.string()));
    FAIL();
  } catch (const OpenniError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open recording"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// speed=0 hands out every frame however slow the reader (OpenNI's manual playback).
TEST_F(OniPlayback, PlaysEveryFrameThenEnds) {
  Openni2RgbdSource source(options("?speed=0"));
  const int recorded = pairs_in(source);
  EXPECT_GE(recorded, 10);
  const Played p = play(source);
  EXPECT_TRUE(p.ended);
  EXPECT_EQ(p.frames, recorded);
  EXPECT_EQ(source.state(), SourceState::Ended);
  RgbdFrame frame;
  EXPECT_EQ(source.read(frame, 10ms), ReadResult::EndOfStream);  // and stays ended
}

TEST_F(OniPlayback, SpeedScalesPlaybackTime) {
  Openni2RgbdSource normal(options("?speed=1"));
  const int n = pairs_in(normal);
  const Played at_1 = play(normal);
  Openni2RgbdSource fast(options("?speed=4"));
  const Played at_4 = play(fast);
  Openni2RgbdSource fastest(options("?speed=0"));
  const Played at_0 = play(fastest);
  // At speed 1 and 4 OpenNI drops the frames the reader was late for: 0-2 of 12 alone, 4 of 12
  // with four copies of this test beside an ASan suite on 2 cores (2026-11-23); manual mode (0)
  // loses none.
  EXPECT_TRUE(at_1.ended && at_4.ended && at_0.ended);
  EXPECT_GE(at_1.frames, n / 2);
  EXPECT_GE(at_4.frames, n / 2);
  EXPECT_EQ(at_0.frames, n);
  const double recorded_s = (n - 1) * 0.033;
  EXPECT_GE(at_1.took.count(), 0.8 * recorded_s);
  EXPECT_LT(at_4.took.count(), 0.6 * at_1.took.count());
  EXPECT_LT(at_0.took.count(), at_4.took.count());
  std::printf(
      "[ MEASURE ] .oni %d RGB-D frames 320x240: speed=1 %.3f s, speed=4 %.3f s, "
      "speed=0 %.3f s (%.0f fps)\n",
      n, at_1.took.count(), at_4.took.count(), at_0.took.count(), n / at_0.took.count());
}

TEST_F(OniPlayback, RepeatStartsOverWithTimestampsStillIncreasing) {
  Openni2RgbdSource source(options("?repeat=1&speed=0"));
  const int n = pairs_in(source);
  const Played p = play(source, 2 * n + 3);
  EXPECT_FALSE(p.ended);
  EXPECT_EQ(p.frames, 2 * n + 3);  // play() checked the timestamps across the wrap
  EXPECT_EQ(source.state(), SourceState::Streaming);
}

TEST_F(OniPlayback, OpensThroughTheRigFactory) {
  const auto t0 = std::chrono::steady_clock::now();
  Rig rig = open_rig("openni2:" + file_.string() + "?speed=0");
  const double open_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(rig.rgbd);
  EXPECT_FALSE(rig.fisheye);
  EXPECT_EQ(rig.rgbd->name(), "openni2:" + file_.string());
  EXPECT_EQ(rig.calibration.rgb.intrinsics().width, 320);
  EXPECT_EQ(rig.calibration.rgb.intrinsics().height, 240);
  RgbdFrame frame;
  ReadResult r = ReadResult::NoFrameYet;
  for (int i = 0; i < 20 && r != ReadResult::Frame; ++i) r = rig.rgbd->read(frame, 100ms);
  EXPECT_EQ(r, ReadResult::Frame);
  std::printf("[ MEASURE ] openni2 .oni open (rig factory): %.1f ms\n", open_ms);
}

TEST(Openni2Rig, FactoryRejectsBadSpecsClearly) {
  EXPECT_THROW(open_rig("openni2:Dummy?bogus=1"), std::invalid_argument);
  EXPECT_THROW(open_rig("openni2:/nonexistent/x.oni"), OpenniError);
}

}  // namespace
}  // namespace probeless::openni2
