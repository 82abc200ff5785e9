// Radiance RGBE and OpenEXR reading and writing: the real probes of ../shared/data, round trips,
// the three Radiance scanline encodings, and errors that name the file.
#include "drivers/io/hdr_image.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <string>

#include "support/test_data.hpp"

namespace probeless {
namespace {

std::vector<std::uint8_t> bytes_of(const std::string& s) {
  return {s.begin(), s.end()};
}

void write_bytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

// Radiance values spanning ten decades, with zeros, constant stretches (runs) and noise.
ImageRGBF test_image(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> log10v(-5, 5), unit(0, 1);
  ImageRGBF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        float v = std::pow(10.0f, log10v(rng));
        if (x % 17 < 6) v = 0.25f * (c + 1);  // runs
        if (x % 23 == 0) v = 0;
        img.at(x, y, c) = v;
      }
  return img;
}

// RGBE keeps 8 bits of the largest channel: every channel is within max/128 below its value.
void expect_rgbe_close(const ImageRGBF& original, const ImageRGBF& decoded) {
  ASSERT_EQ(decoded.width(), original.width());
  ASSERT_EQ(decoded.height(), original.height());
  for (int y = 0; y < original.height(); ++y)
    for (int x = 0; x < original.width(); ++x) {
      const float m = std::max({original.at(x, y, 0), original.at(x, y, 1), original.at(x, y, 2)});
      for (int c = 0; c < 3; ++c) {
        const float o = original.at(x, y, c), d = decoded.at(x, y, c);
        ASSERT_LE(d, o) << x << "," << y;
        ASSERT_LE(o - d, m / 128) << x << "," << y;
      }
    }
}

TEST(RadianceHdr, ReadsTheLightProbes) {
  PROBELESS_REQUIRE_DATA("hdr/probes/uffizi.hdr");
  for (const char* name : {"uffizi", "grace", "pisa"}) {
    const auto path = testing::shared_data_dir() / "hdr/probes" / (std::string(name) + ".hdr");
    const ImageRGBF img = read_hdr_image(path);
    EXPECT_EQ(img.width(), 256) << name;
    EXPECT_EQ(img.height(), 128) << name;
    float lo = INFINITY, hi = 0;
    for (float v : img.elements()) {
      ASSERT_TRUE(std::isfinite(v) && v >= 0) << name;
      if (v > 0) lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    EXPECT_GT(hi / lo, 1e3) << name << ": a light probe spans many stops";
    // The codec is idempotent on decoded values: encode -> decode gives them back exactly.
    EXPECT_EQ(decode_radiance_hdr(encode_radiance_hdr(img), "re-encoded"), img) << name;
  }
}

TEST(RadianceHdr, ReadsThePolyHavenMaps) {
  PROBELESS_REQUIRE_DATA("hdr/polyhaven/studio_small_03_1k.hdr");
  for (const char* name : {"studio_small_03_1k", "st_fagans_interior_1k"}) {
    const ImageRGBF img =
        read_hdr_image(testing::shared_data_dir() / "hdr/polyhaven" / (std::string(name) + ".hdr"));
    EXPECT_EQ(img.width(), 1024) << name;
    EXPECT_EQ(img.height(), 512) << name;
  }
}

TEST(RadianceHdr, RoundTripsThroughAFile) {
  const auto dir = testing::scratch_dir();
  // 300 wide: new-style RLE; 5 wide: too narrow for RLE, flat pixels.
  for (int w : {300, 5}) {
    const ImageRGBF img = test_image(w, 7, static_cast<unsigned>(w));
    const auto path = dir / ("probe" + std::to_string(w) + ".HDR");
    write_hdr_image(path, img);
    EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
    expect_rgbe_close(img, read_hdr_image(path));
  }
}

TEST(RadianceHdr, RleIsSmallerOnFlatImages) {
  const ImageRGBF flat(512, 64, 0.5f);
  EXPECT_LT(encode_radiance_hdr(flat).size(), 512u * 64 / 10);
  EXPECT_EQ(decode_radiance_hdr(encode_radiance_hdr(flat), "flat"), flat);
}

TEST(RadianceHdr, DecodesFlatAndOldStyleRunScanlines) {
  // Width 8 without the 2,2 marker: flat pixels; then (1,1,1,n) repeats the previous pixel.
  std::string file = "#?RGBE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n";
  const std::string a = {char(128), char(64), char(0), char(129)};  // (1, 0.5, 0) * 2
  const std::string b = {char(1), char(1), char(1), char(7)};
  file += a + a + a + a + a + a + a + a;  // row 0: eight literal pixels
  file += a + b;                          // row 1: one pixel, repeated 7 times
  const ImageRGBF img = decode_radiance_hdr(bytes_of(file), "old");
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 8; ++x) {
      EXPECT_FLOAT_EQ(img.at(x, y, 0), 1.0f);
      EXPECT_FLOAT_EQ(img.at(x, y, 1), 0.5f);
      EXPECT_FLOAT_EQ(img.at(x, y, 2), 0.0f);
    }
}

TEST(RadianceHdr, BottomUpAndExposure) {
  ImageRGBF img(9, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 9; ++x) img.at(x, y, 0) = img.at(x, y, 1) = img.at(x, y, 2) = y + 1.0f;
  std::vector<std::uint8_t> bytes = encode_radiance_hdr(img);
  std::string text(bytes.begin(), bytes.end());
  // Same scanlines declared bottom-up, with two EXPOSURE lines (cumulative: 0.5 * 4 = 2).
  const auto res = text.find("-Y 3");
  text.replace(res, 4, "+Y 3");
  text.insert(text.find("\n\n"), "\nEXPOSURE= 0.5\nEXPOSURE=4");
  const ImageRGBF flipped = decode_radiance_hdr(bytes_of(text), "flipped");
  for (int y = 0; y < 3; ++y) EXPECT_FLOAT_EQ(flipped.at(4, y, 1), (3 - y) / 2.0f);
}

TEST(RadianceHdr, ClampsWhatRgbeCannotHold) {
  ImageRGBF img(2, 1);
  img.at(0, 0, 0) = -3;
  img.at(0, 0, 1) = NAN;
  img.at(0, 0, 2) = 1;
  img.at(1, 0, 0) = INFINITY;
  const ImageRGBF back = decode_radiance_hdr(encode_radiance_hdr(img), "clamped");
  EXPECT_EQ(back.at(0, 0, 0), 0);
  EXPECT_EQ(back.at(0, 0, 1), 0);
  EXPECT_EQ(back.at(0, 0, 2), 1);
  EXPECT_GT(back.at(1, 0, 0), 1e37f);
  EXPECT_TRUE(std::isfinite(back.at(1, 0, 0)));
}

std::string error_of(const std::vector<std::uint8_t>& bytes) {
  try {
    decode_radiance_hdr(bytes, "broken.hdr");
  } catch (const ImageFileError& e) {
    EXPECT_EQ(e.path(), "broken.hdr");
    return e.what();
  }
  ADD_FAILURE() << "no ImageFileError";
  return {};
}

TEST(RadianceHdr, ErrorsNameTheFileAndTheProblem) {
  const std::vector<std::uint8_t> good = encode_radiance_hdr(test_image(40, 6, 1));
  std::vector<std::uint8_t> truncated(good.begin(), good.end() - 30);
  EXPECT_NE(error_of(truncated).find("broken.hdr: truncated: pixel data ends in row 5"),
            std::string::npos)
      << error_of(truncated);
  EXPECT_NE(error_of(bytes_of("P6\n2 2\n255\n")).find("not a Radiance"), std::string::npos);
  EXPECT_NE(error_of(bytes_of("#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\1\1\1\1"))
                .find("unsupported FORMAT 32-bit_rle_xyze"),
            std::string::npos);
  EXPECT_NE(error_of(bytes_of("#?RADIANCE\n\n+X 1 -Y 1\n")).find("unsupported resolution"),
            std::string::npos);
  EXPECT_NE(error_of(bytes_of("#?RADIANCE\n\n-Y 0 +X 4\n")).find("bad image size"),
            std::string::npos);
  EXPECT_NE(error_of(bytes_of("#?RADIANCE\n\n-Y 99999 +X 99999\n")).find("bad image size"),
            std::string::npos);
  EXPECT_NE(error_of(bytes_of("#?RADIANCE\nFORMAT=32-bit_rle_rgbe")).find("truncated header"),
            std::string::npos);
  // A run that overflows the scanline.
  std::string overflow = "#?RADIANCE\n\n-Y 1 +X 8\n";
  overflow += std::string{2, 2, 0, 8, char(128 + 9), 1};
  EXPECT_NE(error_of(bytes_of(overflow)).find("bad run length in scanline 0"), std::string::npos);
}

TEST(HdrImage, FileErrorsNameTheFile) {
  const auto dir = testing::scratch_dir();
  try {
    read_hdr_image(dir / "missing.hdr");
    FAIL();
  } catch (const ImageFileError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.hdr"), std::string::npos);
  }
  EXPECT_THROW(read_hdr_image(dir / "missing.exr"), ImageFileError);
  EXPECT_THROW(read_hdr_image(dir / "image.png"), ImageFileError);
  EXPECT_THROW(write_hdr_image(dir / "image.tiff", ImageRGBF(2, 2)), ImageFileError);
  EXPECT_THROW(write_hdr_image(dir / "empty.exr", ImageRGBF()), ImageFileError);
  EXPECT_THROW(write_hdr_image(dir / "no/such/dir/x.hdr", ImageRGBF(2, 2)), ImageFileError);
  EXPECT_THROW(write_hdr_image(dir / "no/such/dir/x.exr", ImageRGBF(2, 2)), ImageFileError);
  // Not an EXR at all, and an EXR cut short.
  write_bytes(dir / "text.exr", bytes_of("hello"));
  EXPECT_THROW(read_hdr_image(dir / "text.exr"), ImageFileError);
  write_hdr_image(dir / "whole.exr", test_image(64, 64, 3));
  const auto size = std::filesystem::file_size(dir / "whole.exr");
  std::filesystem::copy_file(dir / "whole.exr", dir / "cut.exr");
  std::filesystem::resize_file(dir / "cut.exr", size / 2);
  try {
    read_hdr_image(dir / "cut.exr");
    FAIL();
  } catch (const ImageFileError& e) {
    EXPECT_NE(std::string(e.what()).find("cut.exr"), std::string::npos) << e.what();
  }
}

TEST(OpenExr, FloatRoundTripIsExact) {
  ImageRGBF img = test_image(37, 11, 9);
  img.at(3, 4, 1) = -2.5f;  // EXR keeps what RGBE cannot
  img.at(5, 6, 2) = 3e30f;
  const auto path = testing::scratch_dir() / "map.exr";
  write_hdr_image(path, img);
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  EXPECT_EQ(read_hdr_image(path), img);
}

TEST(OpenExr, HalfRoundTripKeepsElevenBits) {
  const ImageRGBF img = test_image(16, 9, 4);
  const auto path = testing::scratch_dir() / "map_half.exr";
  write_hdr_image(path, img, {.exr_half = true});
  const ImageRGBF back = read_hdr_image(path);
  ASSERT_EQ(back.width(), 16);
  for (std::size_t i = 0; i < img.elements().size(); ++i) {
    const float o = img.elements()[i], b = back.elements()[i];
    if (o < 6.2e-5f || o > 65000) continue;  // outside half's normal range
    EXPECT_NEAR(b, o, o * std::ldexp(1.0f, -11)) << i;
  }
  EXPECT_LT(std::filesystem::file_size(path), 16u * 9 * 3 * 4);
}

}  // namespace
}  // namespace probeless
