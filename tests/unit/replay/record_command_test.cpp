// `probeless record` end to end: the binary records a source, the replay sources read it back.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "app/cli/progress.hpp"
#include "drivers/replay/recording.hpp"
#include "drivers/replay/replay_source.hpp"
#include "drivers/rig_factory.hpp"
#include "recording_fixture.hpp"
#include "support/test_data.hpp"
#include "tum_fixture.hpp"

namespace probeless::replay {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

struct RunResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

RunResult run_probeless(const std::string& args) {
  const char* binary = std::getenv("PROBELESS_BINARY");
  RunResult result;
  if (!binary || !*binary) return result;
  const std::string command = std::string("'") + binary + "' " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) result.output += buffer;
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

#define REQUIRE_BINARY()                                                         \
  do {                                                                           \
    const char* b = std::getenv("PROBELESS_BINARY");                             \
    if (!b || !*b || !fs::exists(b)) GTEST_SKIP() << "PROBELESS_BINARY not set"; \
  } while (0)

template <typename FrameT, typename SourceT>
std::vector<FrameT> read_all(SourceT& source) {
  std::vector<FrameT> frames;
  FrameT f;
  while (true) {
    const ReadResult r = source.read(f, 1000ms);
    if (r == ReadResult::EndOfStream) break;
    EXPECT_EQ(r, ReadResult::Frame) << source.last_error();
    if (r != ReadResult::Frame) break;
    frames.push_back(f);
  }
  return frames;
}

TEST(RecordCommand, CopiesARecordingExactly) {
  REQUIRE_BINARY();
  const fs::path base = testing::scratch_dir();
  const auto frames = testing::make_test_frames(5);
  testing::write_recording(base / "original", frames);
  const std::string spec = "replay:" + (base / "original").string() + "?realtime=0";
  const RunResult r =
      run_probeless("record --source '" + spec + "' --frames 4 '" + (base / "copy").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("4 RGB-D frames"), std::string::npos) << r.output;
  // No progress bar when stderr is not a terminal.
  EXPECT_EQ(r.output.find('\r'), std::string::npos) << r.output;

  Rig copy = open_replay_rig(base / "copy", PlaybackOptions{false, false, false});
  const auto rgbd = read_all<RgbdFrame>(*copy.rgbd);
  ASSERT_EQ(rgbd.size(), 4u);
  for (std::size_t i = 0; i < rgbd.size(); ++i) testing::expect_same(rgbd[i], frames.rgbd[i]);
  // Fisheye frames up to the last RGB-D frame's time (5.060000123 s): 5.003 ... 5.048.
  const auto fisheye = read_all<FisheyeFrame>(*copy.fisheye);
  ASSERT_EQ(fisheye.size(), 4u);
  for (std::size_t i = 0; i < fisheye.size(); ++i)
    testing::expect_same(fisheye[i], frames.fisheye[i]);
  EXPECT_EQ(Recording::open(base / "copy")->manifest().source, spec);
}

TEST(RecordCommand, RefusesNonEmptyDirectoryUnlessForced) {
  REQUIRE_BINARY();
  const fs::path base = testing::scratch_dir();
  testing::write_recording(base / "original", testing::make_test_frames(2));
  testing::write_recording(base / "existing", testing::make_test_frames(1));
  const std::string source = "--source 'replay:" + (base / "original").string() + "?realtime=0' ";
  RunResult r = run_probeless("record " + source + "'" + (base / "existing").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("not empty"), std::string::npos) << r.output;
  r = run_probeless("record --force --no-truth " + source + "'" + (base / "existing").string() +
                    "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rec = Recording::open(base / "existing");
  EXPECT_EQ(rec->rgbd().size(), 2u);  // the source's end, no --frames
  EXPECT_FALSE(rec->rgbd()[0].truth.present);
}

// A TUM sequence has no fisheye: the recording holds RGB-D frames and a calibration without
// a [fisheye] table, and replays with no fisheye source.
TEST(RecordCommand, RecordsATumSequenceWithoutFisheye) {
  REQUIRE_BINARY();
  const TumFixture tum = make_tum_sequence();
  const fs::path out = testing::scratch_dir() / "from_tum";
  const RunResult r = run_probeless("record --source 'tum:" + tum.dir.string() + "?realtime=0' '" +
                                    out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;

  Rig copy = open_replay_rig(out, PlaybackOptions{false, false, false});
  EXPECT_EQ(copy.fisheye, nullptr);
  EXPECT_EQ(copy.calibration.fisheye, nullptr);
  const auto rgbd = read_all<RgbdFrame>(*copy.rgbd);
  ASSERT_EQ(rgbd.size(), 3u);  // the three associated pairs
  for (std::size_t i = 0; i < rgbd.size(); ++i) {
    EXPECT_EQ(rgbd[i].colour, tum.colour[i]) << i;
  }
}

// The sim through the CLI: the fisheye thread moves each frame it reads into `pending` and
// reads the next one into the moved-from frame; that used to die with SIGSEGV every time.
TEST(RecordCommand, RecordsTheSim) {
  REQUIRE_BINARY();
  const fs::path out = testing::scratch_dir() / "from_sim";
  const RunResult r = run_probeless(
      "record --source 'sim:realtime=0,fisheye_size=64' --frames 5 '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("5 RGB-D frames"), std::string::npos) << r.output;

  Rig copy = open_replay_rig(out, PlaybackOptions{false, false, false});
  ASSERT_NE(copy.fisheye, nullptr);
  EXPECT_EQ(read_all<RgbdFrame>(*copy.rgbd).size(), 5u);
  // The fisheye keeps behind the RGB-D stream: frames up to the last RGB-D frame's time,
  // several of them (more than one is what reuses a moved-from frame).
  const auto fisheye = read_all<FisheyeFrame>(*copy.fisheye);
  EXPECT_GE(fisheye.size(), 2u);
  for (const auto& f : fisheye) EXPECT_FALSE(f.raw.empty());
}

TEST(RecordCommand, BadSourceIsAnError) {
  REQUIRE_BINARY();
  const fs::path base = testing::scratch_dir();
  RunResult r = run_probeless("record --source bogus:x '" + (base / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("valid: sim"), std::string::npos) << r.output;
  r = run_probeless("record --source 'replay:" + (base / "nothing").string() + "' '" +
                    (base / "out2").string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("not a directory"), std::string::npos) << r.output;
}

TEST(RigFactory, UnknownSchemeListsValidOnes) {
  try {
    (void)open_rig("webcam:0");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    for (const char* s : {"sim", "replay:DIR", "tum:DIR"}) {
      EXPECT_NE(what.find(s), std::string::npos) << what;
    }
  }
  EXPECT_THROW((void)open_rig("replay:"), std::invalid_argument);
  EXPECT_THROW((void)open_rig("replay:/x?realtime=maybe"), std::invalid_argument);
  EXPECT_THROW((void)open_rig("tum:/x?speed=2"), std::invalid_argument);
}

TEST(RigFactory, OpensRecordingsWithOptions) {
  const fs::path dir = testing::scratch_dir() / "rec";
  const auto frames = testing::make_test_frames(2, false);
  testing::write_recording(dir, frames);
  Rig rig = open_rig("replay:" + dir.string() + "?realtime=0&loop=1");
  EXPECT_EQ(rig.rgbd->name(), "replay:" + dir.string());
  RgbdFrame f;
  for (int i = 0; i < 3; ++i) ASSERT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);
  EXPECT_EQ(f.colour, frames.rgbd[0].colour);  // looped
}

TEST(ProgressBar, RendersWithinWidth) {
  using cli::ProgressBar;
  const std::string line = ProgressBar::render("record", 30, 120, 1.0, "fisheye 29", 80);
  EXPECT_LE(line.size(), 79u);
  EXPECT_NE(line.find("30/120"), std::string::npos) << line;
  EXPECT_NE(line.find("25%"), std::string::npos) << line;
  EXPECT_NE(line.find("ETA 0:03"), std::string::npos) << line;
  EXPECT_NE(line.find("[###"), std::string::npos) << line;
  EXPECT_NE(line.find("#...."), std::string::npos) << line;
  EXPECT_NE(line.find("fisheye 29"), std::string::npos) << line;
  EXPECT_LE(ProgressBar::render("record", 5, 0, 2.0, "", 20).size(), 19u);
  EXPECT_NE(ProgressBar::render("record", 5, 0, 2.0, "", 80).find("2.5/s"), std::string::npos);
}

}  // namespace
}  // namespace probeless::replay
