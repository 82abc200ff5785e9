#include "drivers/replay/recording.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "drivers/io/png.hpp"
#include "drivers/replay/replay_source.hpp"
#include "recording_fixture.hpp"
#include "support/test_data.hpp"

namespace probeless::replay {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using probeless::testing::expect_same;
using probeless::testing::make_test_frames;
using probeless::testing::write_recording;

using probeless::testing::read_text;
using probeless::testing::write_text;

// Replaces the first occurrence of `from` in file `p`.
void edit(const fs::path& p, const std::string& from, const std::string& to) {
  std::string text = read_text(p);
  const auto pos = text.find(from);
  ASSERT_NE(pos, std::string::npos) << from << " not in " << p;
  text.replace(pos, from.size(), to);
  write_text(p, text);
}

// Expects Recording::open(dir) to throw a ParseError on `file` at `line` whose message
// contains `fragment`.
void expect_open_error(const fs::path& dir, const fs::path& file, int line,
                       const std::string& fragment) {
  try {
    (void)Recording::open(dir);
    ADD_FAILURE() << "opened a broken recording";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.source(), file.string()) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

PlaybackOptions fast() {
  PlaybackOptions o;
  o.realtime = false;
  return o;
}

RecordingWriterOptions writer_options(bool truth, bool overwrite, std::string source = {}) {
  RecordingWriterOptions o;
  o.write_truth = truth;
  o.overwrite = overwrite;
  o.source = std::move(source);
  return o;
}

TEST(Recording, ReplaysFramesAndMetadataExactly) {
  const fs::path dir = testing::scratch_dir() / "rec";
  const auto frames = make_test_frames(6);
  write_recording(dir, frames, writer_options(true, false, "test:frames"));

  Rig rig = open_replay_rig(dir, fast());
  ASSERT_TRUE(rig.rgbd);
  ASSERT_TRUE(rig.fisheye);
  EXPECT_EQ(to_toml(rig.calibration), to_toml(testing::test_calibration()));
  std::vector<RgbdFrame> rgbd;
  RgbdFrame f;
  while (rig.rgbd->read(f, 10ms) == ReadResult::Frame) rgbd.push_back(f);
  EXPECT_EQ(rig.rgbd->state(), SourceState::Ended);
  EXPECT_EQ(rig.rgbd->read(f, 10ms), ReadResult::EndOfStream);
  ASSERT_EQ(rgbd.size(), frames.rgbd.size());
  for (std::size_t i = 0; i < rgbd.size(); ++i) expect_same(rgbd[i], frames.rgbd[i]);
  // Consecutive frames that shared a light share it again.
  EXPECT_EQ(rgbd[0].truth->light, rgbd[1].truth->light);
  EXPECT_NE(rgbd[2].truth->light, rgbd[3].truth->light);

  std::vector<FisheyeFrame> fisheye;
  FisheyeFrame g;
  rig.fisheye->set_next_exposure(ExposureStamp{});  // ignored
  while (rig.fisheye->read(g, 10ms) == ReadResult::Frame) fisheye.push_back(g);
  ASSERT_EQ(fisheye.size(), frames.fisheye.size());
  for (std::size_t i = 0; i < fisheye.size(); ++i) expect_same(fisheye[i], frames.fisheye[i]);

  const auto rec = Recording::open(dir);
  EXPECT_EQ(rec->manifest().source, "test:frames");
  EXPECT_EQ(rec->manifest().rgbd_frames, 6);
  EXPECT_EQ(rec->manifest().fisheye_frames, 6);
  // The trajectory is TUM's format.
  const std::string gt = read_text(dir / "groundtruth.txt");
  EXPECT_NE(gt.find("# timestamp tx ty tz qx qy qz qw\n5.000000123 0 "), std::string::npos) << gt;
}

TEST(Recording, WithoutTruth) {
  const fs::path dir = testing::scratch_dir() / "rec";
  write_recording(dir, make_test_frames(2), writer_options(false, false));
  EXPECT_FALSE(fs::exists(dir / "truth"));
  EXPECT_FALSE(fs::exists(dir / "groundtruth.txt"));
  Rig rig = open_replay_rig(dir, fast());
  RgbdFrame f;
  ASSERT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);
  EXPECT_EQ(f.truth, nullptr);
}

TEST(Recording, LoopKeepsSequenceAndTimeIncreasing) {
  const fs::path dir = testing::scratch_dir() / "rec";
  const auto frames = make_test_frames(3, false);
  write_recording(dir, frames);
  PlaybackOptions options = fast();
  options.loop = true;
  Rig rig = open_replay_rig(dir, options);
  RgbdFrame f;
  std::vector<RgbdFrame> got;
  for (int i = 0; i < 7; ++i) {
    ASSERT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);
    got.push_back(f);
  }
  for (int i = 0; i < 3; ++i)
    expect_same(got[static_cast<std::size_t>(i)], frames.rgbd[static_cast<std::size_t>(i)]);
  for (std::size_t i = 1; i < got.size(); ++i) {
    EXPECT_EQ(got[i].sequence, got[i - 1].sequence + 1);
    EXPECT_GT(got[i].timestamp_ns, got[i - 1].timestamp_ns);
  }
  EXPECT_EQ(got[3].colour, frames.rgbd[0].colour);
  // Span: first frame of either stream to one RGB-D period after the last of either.
  const TimestampNs last =
      std::max(frames.fisheye.back().timestamp_ns, frames.rgbd.back().timestamp_ns);
  const TimestampNs span = last - frames.rgbd.front().timestamp_ns + 20'000'000;
  EXPECT_EQ(got[3].timestamp_ns, frames.rgbd[0].timestamp_ns + span);
}

TEST(Recording, RealtimePacingNeverBlocksBeyondTimeout) {
  const fs::path dir = testing::scratch_dir() / "rec";
  const auto frames = make_test_frames(4, false);  // RGB-D every 20 ms
  write_recording(dir, frames);
  PlaybackOptions options;
  options.realtime = true;
  Rig rig = open_replay_rig(dir, options);
  RgbdFrame f;
  const auto start = std::chrono::steady_clock::now();     // the clock starts in the first read
  ASSERT_EQ(rig.rgbd->read(f, 100ms), ReadResult::Frame);  // the first is due at once
  EXPECT_EQ(f.sequence, frames.rgbd[0].sequence);
  // The next is due 20 ms after the start: a 1 ms timeout gives "no frame yet" soon.
  const auto t0 = std::chrono::steady_clock::now();
  if (t0 - start < 15ms) {  // unless the machine is so loaded that it is due already
    EXPECT_EQ(rig.rgbd->read(f, 1ms), ReadResult::NoFrameYet);
    EXPECT_LT(std::chrono::steady_clock::now() - t0, 10ms);
  }
  EXPECT_EQ(rig.rgbd->read(f, 100ms), ReadResult::Frame);
  EXPECT_EQ(f.sequence, frames.rgbd[1].sequence);
  EXPECT_GE(std::chrono::steady_clock::now() - start, 20ms);
  // A reader that sleeps misses frames, as with a camera: it gets the latest one due.
  std::this_thread::sleep_for(45ms);
  ASSERT_EQ(rig.rgbd->read(f, 100ms), ReadResult::Frame);
  EXPECT_EQ(f.sequence, frames.rgbd[3].sequence);
  EXPECT_EQ(rig.rgbd->read(f, 10ms), ReadResult::EndOfStream);
}

TEST(Recording, RebaseMovesTimestampsToNow) {
  const fs::path dir = testing::scratch_dir() / "rec";
  write_recording(dir, make_test_frames(2, false));
  PlaybackOptions options = fast();
  options.rebase = true;
  Rig rig = open_replay_rig(dir, options);
  const TimestampNs before = monotonic_now_ns();
  RgbdFrame f;
  ASSERT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);
  EXPECT_GE(f.timestamp_ns, before);
  EXPECT_LE(f.timestamp_ns, monotonic_now_ns());
}

TEST(Recording, WriterRefusesNonEmptyDirectoryUnlessOverwriting) {
  const fs::path dir = testing::scratch_dir() / "rec";
  write_recording(dir, make_test_frames(1));
  EXPECT_THROW(RecordingWriter(dir, testing::test_calibration()), std::runtime_error);
  write_recording(dir, make_test_frames(2), writer_options(true, true));
  EXPECT_EQ(Recording::open(dir)->rgbd().size(), 2u);
  // Overwriting removes only what a recording consists of.
  write_text(dir / "notes.txt", "mine");
  try {
    RecordingWriter writer(dir, testing::test_calibration(), writer_options(true, true));
    ADD_FAILURE() << "overwrote a directory with foreign files";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("notes.txt"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
}

class BrokenRecording : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = testing::scratch_dir() / "rec";
    write_recording(dir, make_test_frames(3));
  }
  fs::path dir;
};

TEST_F(BrokenRecording, ManifestMissingKey) {
  edit(dir / "manifest.toml", "[fisheye]\nframes = 3\n", "[fisheye]\n");
  expect_open_error(dir, dir / "manifest.toml", 0, "missing key 'fisheye.frames'");
}

TEST_F(BrokenRecording, ManifestBadNumber) {
  const std::string text = read_text(dir / "manifest.toml");
  edit(dir / "manifest.toml", "[rgbd]\nframes = 3", "[rgbd]\nframes = \"three\"");
  int line = 1;
  for (std::size_t i = 0; i < text.find("[rgbd]\nframes"); ++i) line += text[i] == '\n';
  expect_open_error(dir, dir / "manifest.toml", line + 1, "'rgbd.frames' must be an integer");
}

TEST_F(BrokenRecording, ManifestWrongVersion) {
  edit(dir / "manifest.toml", "version = 2", "version = 3");
  expect_open_error(dir, dir / "manifest.toml", 4, "unsupported recording version 3");
}

TEST_F(BrokenRecording, ManifestSyntaxError) {
  edit(dir / "manifest.toml", "version = 2", "version = = 2");
  expect_open_error(dir, dir / "manifest.toml", 4, "");
}

TEST_F(BrokenRecording, IndexBadNumber) {
  edit(dir / "rgbd.csv", "\n101,", "\n1o1,");
  expect_open_error(dir, dir / "rgbd.csv", 3, "bad sequence '1o1'");
}

TEST_F(BrokenRecording, IndexBadExposure) {
  const std::string text = read_text(dir / "fisheye.csv");
  const auto line_start = text.find("\n2,") + 1;
  const auto fields_before_time = 5;
  std::size_t pos = line_start;
  for (int k = 0; k < fields_before_time; ++k) pos = text.find(',', pos) + 1;
  std::string broken = text;
  broken.insert(pos, "x");
  write_text(dir / "fisheye.csv", broken);
  expect_open_error(dir, dir / "fisheye.csv", 4, "bad exposure_time_s");
}

TEST_F(BrokenRecording, IndexWrongColumnCount) {
  edit(dir / "fisheye.csv", ",low,", ",low,extra,");
  expect_open_error(dir, dir / "fisheye.csv", 2, "expected 15 comma-separated fields, got 16");
}

TEST_F(BrokenRecording, IndexBadHeader) {
  edit(dir / "rgbd.csv", "sequence,", "seq,");
  expect_open_error(dir, dir / "rgbd.csv", 1, "unexpected header");
}

TEST_F(BrokenRecording, TruncatedIndex) {
  std::string text = read_text(dir / "rgbd.csv");
  text.erase(text.rfind('\n', text.size() - 2) + 1);  // drop the last line
  write_text(dir / "rgbd.csv", text);
  expect_open_error(dir, dir / "rgbd.csv", 3, "has 2 frames but manifest.toml says 3");
}

TEST_F(BrokenRecording, MissingImageFile) {
  fs::remove(dir / "depth" / "000001.png");
  expect_open_error(dir, dir / "rgbd.csv", 3, "missing file 'depth/000001.png'");
}

TEST_F(BrokenRecording, PathOutsideRecording) {
  edit(dir / "rgbd.csv", "rgb/000000.png", "../rgb/000000.png");
  expect_open_error(dir, dir / "rgbd.csv", 2, "must be a relative path inside the recording");
}

TEST_F(BrokenRecording, TrajectoryMismatch) {
  edit(dir / "groundtruth.txt", "\n5.020000123 ", "\n5.020000124 ");
  expect_open_error(dir, dir / "groundtruth.txt", 4, "does not match rgbd.csv:3");
}

TEST_F(BrokenRecording, MissingCalibration) {
  fs::remove(dir / "calibration.toml");
  expect_open_error(dir, dir / "calibration.toml", 0, "cannot open");
}

TEST_F(BrokenRecording, TruncatedPngIsAReadErrorNamingTheFile) {
  const fs::path png = dir / "rgb" / "000001.png";
  const std::string bytes = read_text(png);
  write_text(png, bytes.substr(0, bytes.size() / 2));
  Rig rig = open_replay_rig(dir, fast());
  RgbdFrame f;
  EXPECT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);
  EXPECT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Error);
  EXPECT_NE(rig.rgbd->last_error().find(png.string()), std::string::npos) << rig.rgbd->last_error();
  EXPECT_NE(rig.rgbd->last_error().find("truncated"), std::string::npos);
  EXPECT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);  // goes on with the next frame
  EXPECT_EQ(f.sequence, 102u);
}

TEST_F(BrokenRecording, CorruptLightFile) {
  const fs::path light = dir / "truth" / "light" / "000000.pfm";
  const std::string bytes = read_text(light);
  write_text(light, bytes.substr(0, bytes.size() - 4));
  Rig rig = open_replay_rig(dir, fast());
  RgbdFrame f;
  EXPECT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Error);
  EXPECT_NE(rig.rgbd->last_error().find(light.string()), std::string::npos)
      << rig.rgbd->last_error();
}

}  // namespace
}  // namespace probeless::replay
