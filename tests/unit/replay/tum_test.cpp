#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "drivers/io/png.hpp"
#include "drivers/replay/tum_source.hpp"
#include "support/test_data.hpp"
#include "tum_fixture.hpp"

namespace probeless::replay {

namespace fs = std::filesystem;

namespace {
using namespace std::chrono_literals;

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}
}  // namespace

// A TUM-layout sequence as the benchmark ships it, tiny: 4 colour and 4 depth images whose
// timestamps interleave as in freiburg1 (depth a few ms off colour), one depth too far away.
TumFixture make_tum_sequence(bool with_groundtruth) {
  TumFixture fx;
  fx.dir = testing::scratch_dir() / "rgbd_dataset_freiburg1_tiny";
  fs::create_directories(fx.dir / "rgb");
  fs::create_directories(fx.dir / "depth");
  const char* rgb_times[] = {"1305031102.175304", "1305031102.211214", "1305031102.243211",
                             "1305031102.275326"};
  // Each depth 3-15 ms from its colour image; the last is 21.7 ms from any (unpaired).
  const char* depth_times[] = {"1305031102.160407", "1305031102.200000", "1305031102.240000",
                               "1305031102.297000"};
  std::string rgb_txt =
      "# color images\n# file: 'rgbd_dataset_freiburg1_tiny.bag'\n# timestamp filename\n";
  std::string depth_txt =
      "# depth maps\n# file: 'rgbd_dataset_freiburg1_tiny.bag'\n# timestamp filename\n";
  for (int i = 0; i < 4; ++i) {
    ImageRGB8 c(8, 6, static_cast<std::uint8_t>(10 * i));
    DepthImage d(8, 6);
    for (int k = 0; k < 48; ++k)
      d.elements()[static_cast<std::size_t>(k)] = static_cast<std::uint16_t>(k * 1000 + i);
    d.at(0, 0) = 0;      // no depth stays 0
    d.at(1, 0) = 5000;   // 1 m
    d.at(2, 0) = 65535;  // 13.107 m
    d.at(3, 0) = 7;      // 1.4 mm -> 1
    d.at(4, 0) = 8;      // 1.6 mm -> 2
    const std::string rgb_name = std::string("rgb/") + rgb_times[i] + ".png";
    const std::string depth_name = std::string("depth/") + depth_times[i] + ".png";
    write_png(fx.dir / rgb_name, c);
    write_png(fx.dir / depth_name, d);
    rgb_txt += std::string(rgb_times[i]) + " " + rgb_name + "\n";
    depth_txt += std::string(depth_times[i]) + "\t" + depth_name + "\r\n";  // tabs, CRLF
    fx.colour.push_back(c);
    fx.depth.push_back(d);
  }
  write_text(fx.dir / "rgb.txt", rgb_txt);
  write_text(fx.dir / "depth.txt", depth_txt);
  if (with_groundtruth) {
    write_text(fx.dir / "groundtruth.txt",
               "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n"
               "1305031102.1000 1.0 2.0 3.0 0.0 0.0 0.0 1.0\n"
               "1305031102.2000 2.0 2.0 3.0 0.0 0.0 0.0 1.0\n"
               "1305031102.2600 3.0 2.0 3.0 0.0 0.0 0.0 2.0\n");  // unnormalised
  }
  return fx;
}

namespace {

TEST(Tum, AssociatesLikeAssociatePy) {
  // Greedy on the smallest difference; each image once; strictly under 20 ms.
  const std::vector<TimestampNs> a = {100'000'000, 110'000'000, 200'000'000, 300'000'000};
  const std::vector<TimestampNs> b = {105'000'000, 108'000'000, 219'999'999, 320'000'000};
  const auto m = associate_by_timestamp(a, b);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0], (std::pair<std::size_t, std::size_t>{0, 0}));  // 5 ms (110 takes 108: 2 ms)
  EXPECT_EQ(m[1], (std::pair<std::size_t, std::size_t>{1, 1}));
  EXPECT_EQ(m[2], (std::pair<std::size_t, std::size_t>{2, 2}));  // 19.999999 ms
  // 300 vs 320: exactly 20 ms is not associated.
}

TEST(Tum, ParsesAssociatesAndConvertsDepth) {
  const TumFixture fx = make_tum_sequence();
  const TumSequence seq = open_tum_sequence(fx.dir);
  ASSERT_EQ(seq.frames.size(), 3u);
  EXPECT_EQ(seq.frames[0].timestamp_ns, 1'305'031'102'175'304'000);
  EXPECT_EQ(seq.frames[0].depth, "depth/1305031102.160407.png");
  EXPECT_EQ(seq.frames[1].depth, "depth/1305031102.200000.png");
  EXPECT_EQ(seq.frames[2].colour, "rgb/1305031102.243211.png");
  EXPECT_EQ(seq.frames[2].depth, "depth/1305031102.240000.png");
  // Default intrinsics.
  EXPECT_EQ(seq.calibration.rgb.intrinsics(),
            (PinholeIntrinsics{640, 480, 525, 525, 319.5, 239.5}));
  EXPECT_EQ(seq.calibration.fisheye, nullptr);

  Rig rig = open_tum_rig(fx.dir, PlaybackOptions{false, false, false});
  EXPECT_EQ(rig.fisheye, nullptr);
  RgbdFrame f;
  ASSERT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);
  EXPECT_EQ(f.sequence, 0u);
  EXPECT_EQ(f.timestamp_ns, 1'305'031'102'175'304'000);
  EXPECT_EQ(f.colour, fx.colour[0]);
  EXPECT_EQ(f.depth.at(0, 0), 0);
  EXPECT_EQ(f.depth.at(1, 0), 1000);
  EXPECT_EQ(f.depth.at(2, 0), 13107);
  EXPECT_EQ(f.depth.at(3, 0), 1);
  EXPECT_EQ(f.depth.at(4, 0), 2);
  EXPECT_EQ(f.depth.at(5, 0), (5000 + 2) / 5);
  // Ground truth interpolated at the colour timestamp: x goes 1 -> 2 over .1 -> .2 s.
  ASSERT_TRUE(f.truth && f.truth->rig_pose);
  EXPECT_NEAR(f.truth->rig_pose->translation.x(), 1.75304, 1e-9);
  ASSERT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);
  ASSERT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);
  EXPECT_EQ(f.colour, fx.colour[2]);
  EXPECT_NEAR(f.truth->rig_pose->rotation.norm(), 1.0, 1e-12);  // normalised
  EXPECT_EQ(rig.rgbd->read(f, 10ms), ReadResult::EndOfStream);
}

TEST(Tum, WithoutGroundTruthFramesHaveNoTruth) {
  const TumFixture fx = make_tum_sequence(false);
  Rig rig = open_tum_rig(fx.dir, PlaybackOptions{false, false, false});
  RgbdFrame f;
  ASSERT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);
  EXPECT_EQ(f.truth, nullptr);
}

void expect_parse_error(const fs::path& dir, const fs::path& file, int line,
                        const std::string& fragment) {
  try {
    (void)open_tum_sequence(dir);
    ADD_FAILURE() << "accepted a malformed sequence";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.source(), file.string()) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Tum, MalformedLinesNameFileAndLine) {
  const TumFixture fx = make_tum_sequence();
  const std::string good_rgb = [&] {
    std::ifstream in(fx.dir / "rgb.txt");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }();
  write_text(fx.dir / "rgb.txt", good_rgb + "1305031102.3 rgb/x.png extra\n");
  expect_parse_error(fx.dir, fx.dir / "rgb.txt", 8, "expected 'timestamp filename'");
  write_text(fx.dir / "rgb.txt", good_rgb + "13050311O2.3 rgb/x.png\n");
  expect_parse_error(fx.dir, fx.dir / "rgb.txt", 8, "bad timestamp");
  write_text(fx.dir / "rgb.txt", good_rgb + "1305031102.3 rgb/missing.png\n");
  expect_parse_error(fx.dir, fx.dir / "rgb.txt", 8, "missing file 'rgb/missing.png'");
  write_text(fx.dir / "rgb.txt", good_rgb);
  write_text(fx.dir / "groundtruth.txt", "# t\n1305031102.1 1 2 3 0 0 0\n");
  expect_parse_error(fx.dir, fx.dir / "groundtruth.txt", 2, "expected 8 fields");
  write_text(fx.dir / "groundtruth.txt",
             "1305031102.1 1 2 3 0 0 0 1\n1305031102.1 1 2 3 0 0 0 1\n");
  expect_parse_error(fx.dir, fx.dir / "groundtruth.txt", 2, "duplicate timestamp");
  fs::remove(fx.dir / "depth.txt");
  expect_parse_error(fx.dir, fx.dir / "depth.txt", 0, "cannot open");
}

TEST(Tum, MismatchedDepthSizeIsAReadError) {
  const TumFixture fx = make_tum_sequence(false);
  write_png(fx.dir / "depth/1305031102.160407.png", DepthImage(4, 4));
  Rig rig = open_tum_rig(fx.dir, PlaybackOptions{false, false, false});
  RgbdFrame f;
  EXPECT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Error);
  EXPECT_NE(rig.rgbd->last_error().find("1305031102.160407.png"), std::string::npos);
  EXPECT_EQ(rig.rgbd->read(f, 10ms), ReadResult::Frame);
}

}  // namespace
}  // namespace probeless::replay
