// Recording the synthetic rig and replaying it gives back exactly what the rig delivered.
#include <gtest/gtest.h>

#include "drivers/replay/recording.hpp"
#include "drivers/replay/recording_writer.hpp"
#include "drivers/replay/replay_source.hpp"
#include "drivers/rig_factory.hpp"
#include "recording_fixture.hpp"
#include "support/test_data.hpp"

namespace probeless::replay {
namespace {

using namespace std::chrono_literals;

TEST(SimRecording, RecordThenReplayIsByteIdentical) {
  const auto dir = testing::scratch_dir() / "sim";
  Rig sim = open_rig("sim:realtime=0,seed=5,fisheye_size=64");
  ASSERT_TRUE(sim.rgbd && sim.fisheye);
  std::vector<RgbdFrame> rgbd(3);
  std::vector<FisheyeFrame> fisheye(3);
  {
    RecordingWriterOptions options;
    options.source = "sim:realtime=0,seed=5,fisheye_size=64";
    RecordingWriter writer(dir, sim.calibration, options);
    for (auto& f : rgbd) {
      ASSERT_EQ(sim.rgbd->read(f, 60'000ms), ReadResult::Frame) << sim.rgbd->last_error();
      writer.append(f);
    }
    for (auto& f : fisheye) {
      ASSERT_EQ(sim.fisheye->read(f, 60'000ms), ReadResult::Frame) << sim.fisheye->last_error();
      writer.append(f);
    }
    writer.finish();
  }
  Rig replay = open_rig("replay:" + dir.string() + "?realtime=0");
  EXPECT_EQ(to_toml(replay.calibration), to_toml(sim.calibration));
  for (const auto& expected : rgbd) {
    RgbdFrame f;
    ASSERT_EQ(replay.rgbd->read(f, 100ms), ReadResult::Frame) << replay.rgbd->last_error();
    testing::expect_same(f, expected);
  }
  for (const auto& expected : fisheye) {
    FisheyeFrame f;
    ASSERT_EQ(replay.fisheye->read(f, 100ms), ReadResult::Frame) << replay.fisheye->last_error();
    testing::expect_same(f, expected);
  }
  RgbdFrame f;
  EXPECT_EQ(replay.rgbd->read(f, 100ms), ReadResult::EndOfStream);
}

}  // namespace
}  // namespace probeless::replay
