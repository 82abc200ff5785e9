// `stamp=1` on a replay: the rebased capture time is drawn into each RGB-D frame and reads
// back; without rebase it is refused (a recorded timestamp is another boot's clock).
#include <gtest/gtest.h>

#include "core/capture_stamp.hpp"
#include "drivers/replay/playback.hpp"
#include "drivers/replay/recording_writer.hpp"
#include "drivers/rig_factory.hpp"
#include "support/test_data.hpp"

namespace probeless::replay {
namespace {

using namespace std::chrono_literals;

TEST(ReplayStamp, StampsTheRebasedCaptureTime) {
  const auto dir = testing::scratch_dir() / "sim";
  {
    Rig sim = open_rig("sim:realtime=0,fisheye_size=64,truth=0");
    RecordingWriter writer(dir, sim.calibration, RecordingWriterOptions{});
    RgbdFrame f;
    for (int i = 0; i < 2; ++i) {
      ASSERT_EQ(sim.rgbd->read(f, 60'000ms), ReadResult::Frame);
      writer.append(f);
    }
    writer.finish();
  }
  Rig replay = open_rig("replay:" + dir.string() + "?realtime=0,rebase=1,stamp=1");
  for (int i = 0; i < 2; ++i) {
    RgbdFrame f;
    const TimestampNs before = monotonic_now_ns();
    ASSERT_EQ(replay.rgbd->read(f, 100ms), ReadResult::Frame) << replay.rgbd->last_error();
    const StampReading r = read_capture_stamp(f.colour);
    ASSERT_EQ(r.result, StampRead::Ok) << to_string(r.result);
    EXPECT_EQ(unwrap_stamp(r.micros, before), f.timestamp_ns / 1000 * 1000);
  }
  Rig plain = open_rig("replay:" + dir.string() + "?realtime=0");
  RgbdFrame f;
  ASSERT_EQ(plain.rgbd->read(f, 100ms), ReadResult::Frame);
  EXPECT_NE(read_capture_stamp(f.colour).result, StampRead::Ok);
}

TEST(ReplayStamp, NeedsRebase) {
  EXPECT_THROW(parse_playback_options("stamp=1", nullptr), std::invalid_argument);
  EXPECT_TRUE(parse_playback_options("stamp=1,rebase=1", nullptr).stamp);
  EXPECT_TRUE(parse_playback_options("rebase=1&stamp=1", nullptr).stamp);
}

}  // namespace
}  // namespace probeless::replay
