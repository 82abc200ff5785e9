#include "kernels/hdr/hdr_conversion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "kernels/hdr/hdr_conversion_reference.hpp"
#include "support/cl_context.hpp"

namespace probeless {
namespace {

using testing::cl_context;

// Raw frames whose pixels are a mix of mid-range, saturated (one channel near full scale),
// black (all channels within the margin, some below the black level) and plain random.
ImageRGB16 random_raw(int w, int h, int bits, std::uint16_t black, unsigned seed) {
  std::mt19937 rng(seed);
  const int white = (1 << bits) - 1;
  std::uniform_int_distribution<int> any(0, white), pick(0, 7), channel(0, 2), small(0, 4);
  ImageRGB16 raw(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint16_t* p = &raw.at(x, y, 0);
      for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint16_t>(any(rng));
      const int kind = pick(rng);
      if (kind == 0) {  // saturated in one channel, at or just below the threshold
        p[channel(rng)] = static_cast<std::uint16_t>(white - small(rng) * (white / 40));
      } else if (kind == 1) {  // black: every channel within a few DN of the black level
        for (int c = 0; c < 3; ++c)
          p[c] = static_cast<std::uint16_t>(std::max(0, black - 2 + small(rng)));
      }
    }
  return raw;
}

// "" when equal, else where and how the first element differs (EXPECT_EQ on images prints
// every byte).
std::string first_difference(const ImageRGBAF& got, const ImageRGBAF& want) {
  if (got.width() != want.width() || got.height() != want.height()) return "size differs";
  for (int y = 0; y < got.height(); ++y) {
    for (int x = 0; x < got.width(); ++x) {
      for (int c = 0; c < 4; ++c) {
        if (got.at(x, y, c) != want.at(x, y, c) &&
            !(std::isnan(got.at(x, y, c)) && std::isnan(want.at(x, y, c))))
          return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                 std::to_string(c) + ": " + std::to_string(got.at(x, y, c)) + " vs " +
                 std::to_string(want.at(x, y, c));
      }
    }
  }
  return "";
}

struct Counts {
  int unusable = 0, usable = 0;
};
Counts count(const ImageRGBAF& img) {
  Counts n;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) (img.at(x, y, 3) > 0.0f ? n.usable : n.unusable)++;
  return n;
}

class HdrConversionTest : public ::testing::TestWithParam<int> {};  // bit depth

TEST_P(HdrConversionTest, MatchesTheReferenceOnEverySize) {
  auto& ctx = cl_context();
  const int bits = GetParam();
  const std::uint16_t black = bits == 8 ? 16 : 256;
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> extra(0, 64);
  auto sizes = testing::kernel_test_sizes();
  for (int k = 0; k < 3; ++k) sizes.emplace_back(1 + 2 * extra(rng), 1 + extra(rng));  // odd
  DeviceImage<float, 4> out;
  unsigned seed = 1;
  Counts total;
  for (const auto& [w, h] : sizes) {
    HdrConversionParams params;
    if (seed % 2 == 1) {  // crop a circle that cuts through the frame
      params.circle_cx = 0.5f * (w - 1) + 0.25f;
      params.circle_cy = 0.5f * (h - 1);
      params.circle_radius = 0.45f * static_cast<float>(std::min(w, h)) + 0.5f;
    }
    HdrConversion conversion(ctx, params);
    const Exposure exposure{0.004 * seed, 3.0 * (seed % 3)};
    const auto host = random_raw(w, h, bits, black, seed++);
    const DeviceImage<std::uint16_t, 3> raw(ctx, host);
    conversion.convert(raw, bits, black, exposure, out);
    const auto expected = hdr_conversion_reference(host, bits, black, exposure, params);
    // Exact: integer flags, single rounded float operations on both sides (FP_CONTRACT OFF).
    EXPECT_EQ(first_difference(out.download(ctx.queue()), expected), "")
        << w << "x" << h << " " << bits << " bit";
    const Counts n = count(expected);
    total.usable += n.usable;
    total.unusable += n.unusable;
  }
  // The frames exercised both outcomes in quantity.
  EXPECT_GT(total.usable, 1000);
  EXPECT_GT(total.unusable, 1000);
}

INSTANTIATE_TEST_SUITE_P(BitDepths, HdrConversionTest, ::testing::Values(8, 12),
                         [](const auto& param_info) {
                           return std::to_string(param_info.param) + "bit";
                         });

// Hand-computed values: 12 bit, black 256, range 3839, E = 0.01 s at 6.0206 dB (g = 2).
TEST(HdrConversionReference, FormulaFlagsAndQuality) {
  const Exposure e{0.01, gain_db_from_linear(2.0)};
  const auto c = hdr_conversion_constants(12, 256, e, {});
  EXPECT_EQ(c.range, 3839);
  EXPECT_EQ(c.saturated_signal, 3648);  // ceil(0.95 * 3839 = 3647.05)
  const double scale = 1.0 / (3839 * 0.02);

  const std::uint16_t mid[3] = {256 + 1000, 256 + 1919, 100};  // blue below black -> 0
  auto px = hdr_convert_pixel(mid, 0, 0, 256, c);
  EXPECT_NEAR(px[0], 1000 * scale, 1e-6 * 1000 * scale);
  EXPECT_NEAR(px[1], 1919 * scale, 1e-6 * 1919 * scale);
  EXPECT_EQ(px[2], 0.0f);
  EXPECT_NEAR(px[3], 2.0 * 1919 / 3839, 1e-6);  // hat of the highest channel, near its peak

  const std::uint16_t saturated[3] = {256 + 3648, 300, 300};
  EXPECT_EQ(hdr_convert_pixel(saturated, 0, 0, 256, c)[3], 0.0f);
  const std::uint16_t just_below[3] = {256 + 3647, 300, 300};
  EXPECT_NEAR(hdr_convert_pixel(just_below, 0, 0, 256, c)[3], 2.0 * 192 / 3839, 1e-6);

  const std::uint16_t black[3] = {258, 258, 0};  // every channel within the margin of 2
  EXPECT_EQ(hdr_convert_pixel(black, 0, 0, 256, c)[3], 0.0f);
  const std::uint16_t barely[3] = {259, 258, 0};  // one channel 3 DN above: usable
  EXPECT_GT(hdr_convert_pixel(barely, 0, 0, 256, c)[3], 0.0f);

  HdrConversionParams crop;
  crop.circle_cx = 10;
  crop.circle_cy = 10;
  crop.circle_radius = 5;
  const auto cc = hdr_conversion_constants(12, 256, e, crop);
  EXPECT_GT(hdr_convert_pixel(mid, 15, 10, 256, cc)[3], 0.0f);  // on the circle: inside
  EXPECT_EQ(hdr_convert_pixel(mid, 15, 11, 256, cc)[3], 0.0f);
  EXPECT_EQ(hdr_convert_pixel(mid, 0, 0, 256, cc)[3], 0.0f);
}

// Pixels exactly on the circle are inside, on the device as in the reference.
TEST(HdrConversion, CircleBoundaryIsInside) {
  auto& ctx = cl_context();
  HdrConversionParams params;
  params.circle_cx = 10;
  params.circle_cy = 10;
  params.circle_radius = 5;
  HdrConversion conversion(ctx, params);
  const ImageRGB16 host(21, 21, 128);
  DeviceImage<float, 4> out;
  conversion.convert(DeviceImage<std::uint16_t, 3>(ctx, host), 8, 16, Exposure{}, out);
  const auto got = out.download(ctx.queue());
  EXPECT_EQ(got, hdr_conversion_reference(host, 8, 16, Exposure{}, params));
  int inside = 0;
  for (int y = 0; y < 21; ++y) {
    for (int x = 0; x < 21; ++x) inside += got.at(x, y, 3) > 0.0f;
  }
  EXPECT_EQ(inside, 81);  // lattice points with dx^2 + dy^2 <= 25
  EXPECT_GT(got.at(15, 10, 3), 0.0f);
  EXPECT_GT(got.at(13, 14, 3), 0.0f);
  EXPECT_EQ(got.at(15, 11, 3), 0.0f);
}

TEST(HdrConversion, OutputFollowsTheRawSize) {
  auto& ctx = cl_context();
  HdrConversion conversion(ctx);
  DeviceImage<float, 4> out(ctx, 5, 5);
  const DeviceImage<std::uint16_t, 3> raw(ctx, ImageRGB16(7, 3, 128));
  conversion.convert(raw, 8, 16, Exposure{}, out);
  EXPECT_EQ(out.width(), 7);
  EXPECT_EQ(out.height(), 3);
  const DeviceImage<std::uint16_t, 3> empty;
  conversion.convert(empty, 8, 16, Exposure{}, out);
  EXPECT_TRUE(out.empty());
}

TEST(HdrConversion, RejectsBadInput) {
  auto& ctx = cl_context();
  HdrConversion conversion(ctx);
  const DeviceImage<std::uint16_t, 3> raw(ctx, ImageRGB16(4, 4, 100));
  DeviceImage<float, 4> out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(conversion.convert(raw, 8, 16, Exposure{0.0, 0.0}, out), std::invalid_argument);
  EXPECT_THROW(conversion.convert(raw, 8, 16, Exposure{-0.01, 0.0}, out), std::invalid_argument);
  EXPECT_THROW(conversion.convert(raw, 8, 16, Exposure{nan, 0.0}, out), std::invalid_argument);
  EXPECT_THROW(conversion.convert(raw, 8, 16, Exposure{0.01, -2000.0}, out),
               std::invalid_argument);  // gain underflows to 0
  EXPECT_THROW(conversion.convert(raw, 0, 0, Exposure{}, out), std::invalid_argument);
  EXPECT_THROW(conversion.convert(raw, 17, 0, Exposure{}, out), std::invalid_argument);
  EXPECT_THROW(conversion.convert(raw, 8, 255, Exposure{}, out), std::invalid_argument);
  EXPECT_THROW(hdr_conversion_reference(ImageRGB16(2, 2), 12, 256, Exposure{0.0, 0.0}),
               std::invalid_argument);
  HdrConversionParams bad;
  bad.saturation_fraction = 0.0f;
  EXPECT_THROW(HdrConversion(ctx, bad), std::invalid_argument);
  bad = {};
  bad.black_margin = -1;
  EXPECT_THROW(HdrConversion(ctx, bad), std::invalid_argument);
  bad = {};
  bad.circle_radius = -3.0f;
  EXPECT_THROW(HdrConversion(ctx, bad), std::invalid_argument);
  try {
    conversion.convert(raw, 8, 16, Exposure{0.0, 0.0}, out);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exposure"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace probeless
