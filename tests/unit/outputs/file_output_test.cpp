#include "app/outputs/file_output.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "app/outputs/jpeg_encoder.hpp"
#include "drivers/io/png.hpp"
#include "support/test_data.hpp"
#include "test_images.hpp"

namespace probeless {
namespace {

using testing::gradient_image;

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

FileOutputFrame frame(std::uint64_t index, int width = 64, int height = 48) {
  FileOutputFrame f;
  f.index = index;
  f.timestamp_ns = static_cast<TimestampNs>(index) * 33'333'333 + 1'000'000'000;
  f.colour =
      std::make_shared<const ImageRGB8>(gradient_image(width, height, static_cast<int>(index)));
  return f;
}

TEST(FileOutput, WritesAJpegSequenceWithAnIndex) {
  const auto dir = testing::scratch_dir() / "out";  // created by the output
  {
    FileOutput out({.dir = dir});
    for (std::uint64_t i = 1; i <= 3; ++i) {
      out.submit(frame(i));
      // Give the writer time, so that nothing is dropped in this test.
      for (int t = 0; t < 500 && out.stats().written < i; ++t) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
    }
    out.stop();
    const FileOutputStats s = out.stats();
    EXPECT_EQ(s.submitted, 3u);
    EXPECT_EQ(s.written, 3u);
    EXPECT_EQ(s.dropped, 0u);
    EXPECT_EQ(s.failed, 0u);
  }
  JpegDecoder decoder;
  for (const char* name : {"frame_000001.jpg", "frame_000002.jpg", "frame_000003.jpg"}) {
    ASSERT_TRUE(std::filesystem::exists(dir / name)) << name;
    const ImageRGB8 image = decoder.decode(read_bytes(dir / name));
    EXPECT_EQ(image.width(), 64);
    EXPECT_EQ(image.height(), 48);
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "matte_000001.png"));
  std::ifstream index(dir / "frames.txt");
  std::string line;
  std::getline(index, line);
  EXPECT_EQ(line, "1.033333 frame_000001.jpg");
}

TEST(FileOutput, WritesPngAndTheMatte) {
  const auto dir = testing::scratch_dir();
  FileOutput out({.dir = dir, .format = ImageFileFormat::Png, .write_matte = true});
  FileOutputFrame f = frame(7);
  ImageF alpha(64, 48, 0.0f);
  alpha.at(10, 10) = 1.0f;
  alpha.at(11, 10) = 0.5f;
  alpha.at(12, 10) = 7.0f;  // clamped
  f.matte = std::make_shared<const ImageF>(alpha);
  out.submit(f);
  FileOutputFrame g = frame(8);
  g.matte = std::make_shared<const ImageGray8>(64, 48, std::uint8_t{77});
  out.submit(g);
  out.stop();
  out.stop();  // twice is fine
  EXPECT_EQ(out.stats().written + out.stats().dropped, 2u);
  if (out.stats().dropped == 0) {
    EXPECT_EQ(read_png_rgb8(dir / "frame_000007.png"), *f.colour);  // lossless
    const ImageGray8 matte = read_png_gray8(dir / "matte_000007.png");
    EXPECT_EQ(matte.at(10, 10), 255);
    EXPECT_EQ(matte.at(11, 10), 128);
    EXPECT_EQ(matte.at(12, 10), 255);
    EXPECT_EQ(matte.at(0, 0), 0);
  }
  EXPECT_EQ(read_png_gray8(dir / "matte_000008.png").at(3, 3), 77);
}

// Frames submitted far faster than they can be written: submit() never waits, the queue
// stays bounded, and every frame is written or counted as dropped.
TEST(FileOutput, DropsWhenBehindWithoutBlocking) {
  const auto dir = testing::scratch_dir();
  FileOutput out({.dir = dir, .format = ImageFileFormat::Png, .queue_capacity = 2});
  constexpr int kFrames = 200;
  auto big = std::make_shared<const ImageRGB8>(testing::noise_image(640, 480, 3));
  for (int i = 1; i <= kFrames; ++i) {
    FileOutputFrame f;
    f.index = static_cast<std::uint64_t>(i);
    f.colour = big;
    out.submit(std::move(f));
  }
  out.stop();
  const FileOutputStats s = out.stats();
  EXPECT_EQ(s.submitted, static_cast<std::uint64_t>(kFrames));
  EXPECT_GT(s.dropped, 0u);
  EXPECT_EQ(s.written + s.dropped, static_cast<std::uint64_t>(kFrames));
  // The newest frame always survives: what is dropped is the oldest waiting one.
  EXPECT_TRUE(std::filesystem::exists(dir / "frame_000200.png"));
}

TEST(FileOutput, CountsWriteErrorsAndCarriesOn) {
  const auto dir = testing::scratch_dir();
  std::filesystem::create_directories(dir / "frame_000001.jpg.tmp");  // fopen fails: a directory
  FileOutput out({.dir = dir});
  out.submit(frame(1));
  out.stop();
  EXPECT_EQ(out.stats().failed, 1u);
  EXPECT_NE(out.stats().last_error.find("frame_000001.jpg"), std::string::npos);
  FileOutput again({.dir = dir});
  again.submit(frame(2));
  again.stop();
  EXPECT_EQ(again.stats().written, 1u);
}

// Writes frames one at a time, waiting for each, so nothing is dropped.
void write_frames(FileOutput& out, std::uint64_t first, std::uint64_t count) {
  for (std::uint64_t i = first; i < first + count; ++i) {
    const auto before = out.stats();
    out.submit(frame(i, 160, 120));
    for (int t = 0; t < 1000; ++t) {
      const auto s = out.stats();
      if (s.written + s.failed > before.written + before.failed || s.full) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }
}

std::uint64_t images_in(const std::filesystem::path& dir, std::uint64_t* bytes = nullptr) {
  std::uint64_t n = 0, total = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().filename().string().starts_with("frame_")) ++n, total += e.file_size();
  }
  if (bytes) *bytes = total;
  return n;
}

// The size cap removes the oldest files (issue #20): the directory stays under max_bytes
// and the newest frame is there.
TEST(FileOutput, SizeCapRemovesTheOldestFiles) {
  const auto dir = testing::scratch_dir() / "capped";
  FileOutput probe({.dir = testing::scratch_dir() / "probe"});
  write_frames(probe, 0, 1);
  probe.stop();
  const std::uint64_t one = probe.stats().bytes;
  ASSERT_GT(one, 0u);
  // Room for about four frames.
  FileOutput out({.dir = dir, .max_bytes = one * 4 + one / 2});
  write_frames(out, 1, 12);
  out.stop();
  const auto s = out.stats();
  EXPECT_EQ(s.written, 12u);
  EXPECT_FALSE(s.full);
  std::uint64_t bytes = 0;
  const std::uint64_t files = images_in(dir, &bytes);
  EXPECT_LE(bytes, one * 4 + one / 2);
  EXPECT_GE(files, 3u);
  EXPECT_LE(files, 5u);
  EXPECT_EQ(s.files, files);
  EXPECT_EQ(s.bytes, bytes);
  EXPECT_EQ(s.removed, 12u - files);
  EXPECT_TRUE(std::filesystem::exists(dir / "frame_000012.jpg"));
  EXPECT_FALSE(std::filesystem::exists(dir / "frame_000001.jpg"));
}

// With when_full = "stop" writing stops at the cap and the status says why.
TEST(FileOutput, SizeCapCanStopTheRecordingWithAClearStatus) {
  const auto dir = testing::scratch_dir() / "stop";
  FileOutput probe({.dir = testing::scratch_dir() / "probe"});
  write_frames(probe, 0, 1);
  probe.stop();
  const std::uint64_t one = probe.stats().bytes;
  FileOutput out({.dir = dir, .max_bytes = one * 3 + one / 2, .stop_when_full = true});
  write_frames(out, 1, 8);
  out.stop();
  const auto s = out.stats();
  EXPECT_TRUE(s.full);
  EXPECT_EQ(s.written, 3u);
  EXPECT_EQ(images_in(dir), 3u);
  EXPECT_TRUE(std::filesystem::exists(dir / "frame_000003.jpg"));
  EXPECT_FALSE(std::filesystem::exists(dir / "frame_000004.jpg"));
  EXPECT_NE(s.last_error.find("output cap reached"), std::string::npos) << s.last_error;
  EXPECT_NE(s.last_error.find(dir.string()), std::string::npos) << s.last_error;
  nlohmann::json status;
  out.add_status(status);
  EXPECT_EQ(status["file_output"]["state"], "full");
  // A restart counts the files already there: the next frame is one too many.
  FileOutput again({.dir = dir, .max_bytes = one * 3 + one / 2, .stop_when_full = true});
  EXPECT_EQ(again.stats().files, 3u);
  write_frames(again, 20, 2);
  again.stop();
  EXPECT_TRUE(again.stats().full);
  EXPECT_EQ(again.stats().written, 0u);
  EXPECT_EQ(images_in(dir), 3u);
}

// The age cap removes files older than keep_minutes, earlier runs' files too, and leaves
// other files alone.
TEST(FileOutput, AgeCapRemovesOldFilesOfEarlierRuns) {
  const auto dir = testing::scratch_dir() / "aged";
  std::filesystem::create_directories(dir);
  const auto two_hours_ago = std::filesystem::file_time_type::clock::now() - std::chrono::hours(2);
  for (const char* name : {"frame_000001.jpg", "matte_000001.png", "notes.txt"}) {
    std::ofstream(dir / name) << "old";
    std::filesystem::last_write_time(dir / name, two_hours_ago);
  }
  std::ofstream(dir / "frame_000002.jpg") << "recent";
  FileOutput out({.dir = dir, .max_age = std::chrono::minutes(60)});
  EXPECT_FALSE(std::filesystem::exists(dir / "frame_000001.jpg"));
  EXPECT_FALSE(std::filesystem::exists(dir / "matte_000001.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "notes.txt")) << "not this output's file";
  EXPECT_TRUE(std::filesystem::exists(dir / "frame_000002.jpg"));
  write_frames(out, 3, 1);
  out.stop();
  EXPECT_EQ(out.stats().removed, 2u);
  EXPECT_EQ(out.stats().files, 2u);
}

// A directory the service cannot write to is an error at start naming it and the fix.
TEST(FileOutput, UnwritableDirectoryIsAClearErrorAtStart) {
  const auto file = testing::scratch_dir() / "a-file";
  std::ofstream(file) << "x";
  for (const auto& dir : {file / "frames", std::filesystem::path("/proc/probeless-frames")}) {
    try {
      FileOutput out({.dir = dir});
      ADD_FAILURE() << dir << " was accepted";
    } catch (const FileOutputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(dir.string()), std::string::npos) << what;
      EXPECT_NE(what.find("not writable"), std::string::npos) << what;
      EXPECT_NE(what.find("ReadWritePaths="), std::string::npos) << what;
    }
  }
}

TEST(FileOutput, Format) {
  EXPECT_EQ(parse_image_file_format("jpeg"), ImageFileFormat::Jpeg);
  EXPECT_EQ(parse_image_file_format("jpg"), ImageFileFormat::Jpeg);
  EXPECT_EQ(parse_image_file_format("png"), ImageFileFormat::Png);
  EXPECT_THROW(parse_image_file_format("gif"), std::invalid_argument);
  EXPECT_THROW(FileOutput({.dir = testing::scratch_dir(), .jpeg_quality = 0}),
               std::invalid_argument);
}

TEST(FileOutput, MatteConversion) {
  ImageF alpha(3, 1);
  alpha.at(0, 0) = -1.0f;
  alpha.at(1, 0) = 0.25f;
  alpha.at(2, 0) = std::numeric_limits<float>::quiet_NaN();
  const ImageGray8 g = matte_to_gray8(alpha);
  EXPECT_EQ(g.at(0, 0), 0);
  EXPECT_EQ(g.at(1, 0), 64);
  EXPECT_EQ(g.at(2, 0), 0);
}

}  // namespace
}  // namespace probeless
