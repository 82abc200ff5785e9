// Recordings that were interrupted (killed, power cut): format version 2's manifest written
// first with `complete = false`, and what Recording::open() salvages from such a directory
// (docs/formats.md "Power loss"). The kill -9 test of the CLI is record_kill_test.cpp.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "drivers/replay/recording.hpp"
#include "drivers/replay/replay_source.hpp"
#include "recording_fixture.hpp"
#include "support/test_data.hpp"

namespace probeless::replay {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using probeless::testing::expect_same;
using probeless::testing::make_test_frames;

using probeless::testing::read_text;
using probeless::testing::write_text;

void append_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::app);
  out << text;
}

std::string open_error(const fs::path& dir) {
  try {
    (void)Recording::open(dir);
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

// A writer that appended `n` frames per stream and was never finished (the process died).
fs::path interrupted_recording(int n, const testing::TestFrames& frames) {
  const fs::path dir = testing::scratch_dir() / "rec";
  RecordingWriter writer(dir, testing::test_calibration());
  for (int i = 0; i < n; ++i) {
    writer.append(frames.rgbd[i]);
    writer.append(frames.fisheye[i]);
  }
  return dir;  // no finish()
}

TEST(RecordingSalvage, ManifestIsWrittenAtStartAndCompletedAtTheEnd) {
  const fs::path dir = testing::scratch_dir() / "rec";
  const auto frames = make_test_frames(2);
  RecordingWriter writer(dir, testing::test_calibration());
  // Before the first frame the directory is already a recording, of no frames.
  auto rec = Recording::open(dir);
  EXPECT_FALSE(rec->manifest().complete);
  EXPECT_EQ(rec->manifest().version, 2);
  EXPECT_TRUE(rec->rgbd().empty());
  writer.append(frames.rgbd[0]);
  EXPECT_EQ(Recording::open(dir)->rgbd().size(), 1u);
  writer.append(frames.rgbd[1]);
  writer.finish();
  rec = Recording::open(dir);
  EXPECT_TRUE(rec->manifest().complete);
  EXPECT_EQ(rec->manifest().rgbd_frames, 2);
  EXPECT_NE(read_text(dir / "manifest.toml").find("complete = true"), std::string::npos);
}

TEST(RecordingSalvage, InterruptedRecordingReplaysItsCompleteFrames) {
  const auto frames = make_test_frames(4);
  const fs::path dir = interrupted_recording(3, frames);
  // What a kill in the middle of frame 3 leaves: its images and pose written, its index
  // line cut short, a half-written PNG of the next frame beside.
  write_text(dir / "rgb" / "000003.png", "\x89PNG\r\n");
  append_text(dir / "rgbd.csv", "103,5060000123,rgb/000003.png,dep");
  append_text(dir / "groundtruth.txt", "5.060000123 1 2 3 0 0 0 1\n5.08000");
  append_text(dir / "fisheye.csv", "3,5");
  const auto rec = Recording::open(dir);
  EXPECT_FALSE(rec->manifest().complete);
  EXPECT_EQ(rec->manifest().rgbd_frames, 3);
  EXPECT_EQ(rec->manifest().fisheye_frames, 3);
  PlaybackOptions fast;
  fast.realtime = false;
  Rig rig = open_replay_rig(dir, fast);
  for (int i = 0; i < 3; ++i) {
    RgbdFrame f;
    ASSERT_EQ(rig.rgbd->read(f, 100ms), ReadResult::Frame) << rig.rgbd->last_error();
    expect_same(f, frames.rgbd[i]);
    FisheyeFrame g;
    ASSERT_EQ(rig.fisheye->read(g, 100ms), ReadResult::Frame) << rig.fisheye->last_error();
    expect_same(g, frames.fisheye[i]);
  }
  RgbdFrame f;
  EXPECT_EQ(rig.rgbd->read(f, 10ms), ReadResult::EndOfStream);
}

TEST(RecordingSalvage, CorruptLinesOfAnInterruptedRecordingAreStillRefused) {
  const auto frames = make_test_frames(3);
  const fs::path dir = interrupted_recording(3, frames);
  const std::string rgbd = read_text(dir / "rgbd.csv");
  // A whole line that does not parse is damage, not an interruption.
  std::string broken = rgbd;
  broken.replace(broken.find("\n101,"), 5, "\n1o1,");
  write_text(dir / "rgbd.csv", broken);
  EXPECT_NE(open_error(dir).find("rgbd.csv:3: bad sequence '1o1'"), std::string::npos)
      << open_error(dir);
  // A complete line naming a file that is not there.
  write_text(dir / "rgbd.csv", rgbd);
  fs::remove(dir / "depth" / "000001.png");
  EXPECT_NE(open_error(dir).find("missing file 'depth/000001.png'"), std::string::npos)
      << open_error(dir);
  // Fewer poses than indexed frames that have one.
  fs::copy_file(dir / "rgb" / "000001.png", dir / "depth" / "000001.png");
  std::string poses = read_text(dir / "groundtruth.txt");
  poses.erase(poses.rfind('\n', poses.size() - 2) + 1);
  write_text(dir / "groundtruth.txt", poses);
  EXPECT_NE(open_error(dir).find("has 2 poses, but rgbd.csv has 3"), std::string::npos)
      << open_error(dir);
}

TEST(RecordingSalvage, CompleteRecordingWithACutLastLineIsRefused) {
  const fs::path dir = testing::scratch_dir() / "rec";
  testing::write_recording(dir, make_test_frames(3));
  std::string text = read_text(dir / "rgbd.csv");
  text.erase(text.size() - 10);  // the writer finished: this is damage
  write_text(dir / "rgbd.csv", text);
  EXPECT_NE(open_error(dir).find("rgbd.csv:4"), std::string::npos) << open_error(dir);
}

TEST(RecordingSalvage, ManifestCompleteMustBeABoolean) {
  const fs::path dir = testing::scratch_dir() / "rec";
  testing::write_recording(dir, make_test_frames(1));
  std::string text = read_text(dir / "manifest.toml");
  text.replace(text.find("complete = true"), 15, "complete = 1");
  write_text(dir / "manifest.toml", text);
  EXPECT_NE(open_error(dir).find("'complete' must be a boolean"), std::string::npos)
      << open_error(dir);
  text.replace(text.find("complete = 1\n"), 13, "");
  write_text(dir / "manifest.toml", text);
  EXPECT_NE(open_error(dir).find("missing key 'complete'"), std::string::npos) << open_error(dir);
}

// Version 1 (no `complete`, manifest written last) still reads, and its counts still bind.
TEST(RecordingSalvage, Version1RecordingsStillRead) {
  const fs::path dir = testing::scratch_dir() / "rec";
  const auto frames = make_test_frames(3);
  testing::write_recording(dir, frames);
  std::string text = read_text(dir / "manifest.toml");
  text.replace(text.find("version = 2\ncomplete = true\n"), 28, "version = 1\n");
  write_text(dir / "manifest.toml", text);
  const auto rec = Recording::open(dir);
  EXPECT_EQ(rec->manifest().version, 1);
  EXPECT_TRUE(rec->manifest().complete);
  EXPECT_EQ(rec->rgbd().size(), 3u);
  // An interrupted version-1 recording had no manifest: still refused, saying why.
  fs::remove(dir / "manifest.toml");
  EXPECT_NE(open_error(dir).find("version-1 recording that was interrupted"), std::string::npos)
      << open_error(dir);
}

TEST(RecordingSalvage, WithoutSyncTheFormatIsTheSame) {
  const fs::path dir = testing::scratch_dir() / "rec";
  const auto frames = make_test_frames(2);
  RecordingWriterOptions options;
  options.sync = false;
  testing::write_recording(dir, frames, options);
  EXPECT_EQ(Recording::open(dir)->rgbd().size(), 2u);
}

}  // namespace
}  // namespace probeless::replay
