#include "drivers/v4l2/pixel_convert.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace probeless::v4l2 {
namespace {

// A flat Bayer frame whose R, G and B sites hold r, g, b: every demosaiced pixel must be
// exactly (r, g, b), whatever its site and at the border too.
TEST(PixelConvert, BayerFlatColourDemosaicsExactlyForEveryOrder) {
  for (BayerOrder order :
       {BayerOrder::RGGB, BayerOrder::BGGR, BayerOrder::GRBG, BayerOrder::GBRG}) {
    PixelFormat f;
    f.layout = PixelLayout::Bayer8;
    f.bayer = order;
    f.bytes_per_line = 8;
    std::vector<std::uint8_t> in(8 * 6);
    // Where each order puts R and B in the 2x2 tile (index y*2+x); the rest are green.
    const int r_site = order == BayerOrder::RGGB   ? 0
                       : order == BayerOrder::BGGR ? 3
                       : order == BayerOrder::GRBG ? 1
                                                   : 2;
    const int b_site = 3 - r_site;
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 8; ++x) {
        const int site = (y & 1) * 2 + (x & 1);
        in[static_cast<std::size_t>(y * 8 + x)] = site == r_site ? 200 : site == b_site ? 20 : 90;
      }
    ImageRGB16 out;
    convert_to_linear_rgb16(in, f, 8, 6, out);
    ASSERT_EQ(out.width(), 8);
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 8; ++x) {
        EXPECT_EQ(out.at(x, y, 0), 200) << static_cast<int>(order) << " " << x << "," << y;
        EXPECT_EQ(out.at(x, y, 1), 90);
        EXPECT_EQ(out.at(x, y, 2), 20);
      }
    EXPECT_EQ(output_bit_depth(f), 8);
  }
}

// Bilinear: a horizontal ramp in the red samples is interpolated linearly between them.
TEST(PixelConvert, BayerInterpolatesBetweenSamples) {
  PixelFormat f;
  f.layout = PixelLayout::Bayer8;
  f.bayer = BayerOrder::RGGB;
  f.bytes_per_line = 8;
  std::vector<std::uint8_t> in(8 * 4, 0);
  for (int y = 0; y < 4; y += 2)
    for (int x = 0; x < 8; x += 2)
      in[static_cast<std::size_t>(y * 8 + x)] = static_cast<std::uint8_t>(10 * x);
  ImageRGB16 out;
  convert_to_linear_rgb16(in, f, 8, 4, out);
  EXPECT_EQ(out.at(2, 0, 0), 20);
  EXPECT_EQ(out.at(3, 0, 0), 30);  // between 20 and 40
  EXPECT_EQ(out.at(5, 2, 0), 50);
}

// 10-bit samples in 16-bit containers scale to 12 bit by 4 (linearity kept); stride padding
// is skipped.
TEST(PixelConvert, Bayer10ScalesToTwelveBitsAndHonoursStride) {
  PixelFormat f;
  f.layout = PixelLayout::Bayer16;
  f.bits = 10;
  f.bayer = BayerOrder::RGGB;
  f.bytes_per_line = 2 * 4 + 6;  // padded rows
  std::vector<std::uint8_t> in(f.bytes_per_line * 2, 0xee);
  const std::uint16_t v[2][4] = {{1023, 100, 1023, 100}, {100, 7, 100, 7}};
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      in[y * f.bytes_per_line + 2 * x] = static_cast<std::uint8_t>(v[y][x] & 0xff);
      in[y * f.bytes_per_line + 2 * x + 1] = static_cast<std::uint8_t>(v[y][x] >> 8);
    }
  ImageRGB16 out;
  convert_to_linear_rgb16(in, f, 4, 2, out);
  EXPECT_EQ(output_bit_depth(f), 12);
  EXPECT_EQ(out.at(0, 0, 0), 4092);
  EXPECT_EQ(out.at(0, 0, 1), 400);
  EXPECT_EQ(out.at(1, 1, 2), 28);
}

TEST(PixelConvert, SrgbAndRec709CurvesAreTheStandardOnes) {
  EXPECT_DOUBLE_EQ(linearise(0, TransferFunction::Srgb), 0.0);
  EXPECT_DOUBLE_EQ(linearise(255, TransferFunction::Srgb), 1.0);
  EXPECT_NEAR(linearise(188, TransferFunction::Srgb), 0.5029, 1e-3);  // sRGB 188 ~ 50 %
  EXPECT_NEAR(linearise(10, TransferFunction::Srgb), 10 / 255.0 / 12.92, 1e-9);
  EXPECT_NEAR(linearise(255, TransferFunction::Rec709), 1.0, 1e-9);
  EXPECT_NEAR(linearise(10, TransferFunction::Rec709), 10 / 255.0 / 4.5, 1e-9);
  EXPECT_DOUBLE_EQ(linearise(128, TransferFunction::Linear), 128 / 255.0);
}

TEST(PixelConvert, Rgb24AndBgr24LineariseThroughTheCurve) {
  PixelFormat f;
  f.layout = PixelLayout::RGB24;
  f.bytes_per_line = 6;
  const std::vector<std::uint8_t> in = {255, 188, 0, 0, 0, 0};
  ImageRGB16 out;
  convert_to_linear_rgb16(in, f, 2, 1, out);
  EXPECT_EQ(out.at(0, 0, 0), 4095);
  EXPECT_NEAR(out.at(0, 0, 1), 0.5029 * 4095, 3);
  EXPECT_EQ(out.at(0, 0, 2), 0);
  f.layout = PixelLayout::BGR24;
  convert_to_linear_rgb16(in, f, 2, 1, out);
  EXPECT_EQ(out.at(0, 0, 2), 4095);
  EXPECT_EQ(out.at(0, 0, 0), 0);
}

// Limited-range BT.601 YUYV: black (16), white (235) and a saturated red decode to the
// linear values their R'G'B' codes have.
TEST(PixelConvert, YuyvLimitedRangeDecodesBlackWhiteAndRed) {
  PixelFormat f;
  f.layout = PixelLayout::YUYV;
  f.bytes_per_line = 8;
  // Y0 U Y1 V for (black, white), then BT.601 red (Y 81, Cb 90, Cr 240) twice.
  const std::vector<std::uint8_t> in = {16, 128, 235, 128, 81, 90, 81, 240};
  ImageRGB16 out;
  convert_to_linear_rgb16(in, f, 4, 1, out);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(out.at(0, 0, c), 0);
    EXPECT_EQ(out.at(1, 0, c), 4095);
  }
  EXPECT_GT(out.at(2, 0, 0), 4000);
  EXPECT_LT(out.at(2, 0, 1), 20);
  EXPECT_LT(out.at(2, 0, 2), 20);
  EXPECT_EQ(output_bit_depth(f), 12);
}

TEST(PixelConvert, ShortBufferAndOddSizesAreRejected) {
  PixelFormat f;
  f.layout = PixelLayout::YUYV;
  f.bytes_per_line = 8;
  ImageRGB16 out;
  const std::vector<std::uint8_t> in(8, 0);
  EXPECT_THROW(convert_to_linear_rgb16(in, f, 4, 2, out), std::invalid_argument);
  f.bytes_per_line = 6;
  EXPECT_THROW(convert_to_linear_rgb16(in, f, 3, 1, out), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::v4l2
