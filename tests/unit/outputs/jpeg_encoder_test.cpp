#include "app/outputs/jpeg_encoder.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "test_images.hpp"

namespace probeless {
namespace {

using testing::gradient_image;
using testing::mean_abs_difference;

TEST(JpegEncoder, RoundTripKeepsSizeAndPicture) {
  const ImageRGB8 image = gradient_image(640, 480);
  JpegEncoder encoder;
  EXPECT_EQ(encoder.quality(), 80);
  const auto jpeg = encoder.encode(image);
  ASSERT_GT(jpeg.size(), 100u);
  EXPECT_EQ(jpeg[0], 0xFF);  // SOI
  EXPECT_EQ(jpeg[1], 0xD8);
  JpegDecoder decoder;
  const ImageRGB8 decoded = decoder.decode(jpeg);
  EXPECT_EQ(decoded.width(), 640);
  EXPECT_EQ(decoded.height(), 480);
  EXPECT_LT(mean_abs_difference(image, decoded), 3.0);
}

TEST(JpegEncoder, OddSizesAndGray) {
  JpegEncoder encoder(90);
  JpegDecoder decoder;
  for (auto [w, h] : {std::pair{1, 1}, {3, 5}, {17, 9}, {641, 479}}) {
    const ImageRGB8 decoded = decoder.decode(encoder.encode(gradient_image(w, h)));
    EXPECT_EQ(decoded.width(), w);
    EXPECT_EQ(decoded.height(), h);
  }
  ImageGray8 gray(33, 21, 200);
  const ImageRGB8 decoded = decoder.decode(encoder.encode(gray));
  ASSERT_EQ(decoded.width(), 33);
  EXPECT_NEAR(decoded.at(10, 10, 0), 200, 2);
  EXPECT_EQ(decoded.at(10, 10, 0), decoded.at(10, 10, 2));
}

TEST(JpegEncoder, QualityTradesSizeForFidelity) {
  const ImageRGB8 image = testing::noise_image(320, 240, 7);
  JpegEncoder encoder(30);
  const std::size_t low = encoder.encode(image).size();
  encoder.set_quality(95);
  const std::size_t high = encoder.encode(image).size();
  EXPECT_LT(low, high);
  EXPECT_THROW(encoder.set_quality(0), std::invalid_argument);
  EXPECT_THROW(encoder.set_quality(101), std::invalid_argument);
  EXPECT_THROW(JpegEncoder(-3), std::invalid_argument);
}

TEST(JpegEncoder, ReusesItsBufferAcrossFramesAndSizes) {
  JpegEncoder encoder;
  const auto first = encoder.encode(gradient_image(640, 480, 1));
  const std::uint8_t* where = first.data();
  const auto second = encoder.encode(gradient_image(640, 480, 2));
  EXPECT_EQ(second.data(), where);
  const auto small = encoder.encode(gradient_image(64, 48, 3));
  EXPECT_EQ(small.data(), where);  // smaller frames fit the same buffer
  JpegDecoder decoder;
  EXPECT_EQ(decoder.decode(small).width(), 64);
}

TEST(JpegEncoder, SharedCopySurvivesTheNextEncode) {
  JpegEncoder encoder;
  const auto shared = encoder.encode_shared(gradient_image(64, 48, 1));
  const std::vector<std::uint8_t> copy = *shared;
  encoder.encode(gradient_image(64, 48, 2));
  EXPECT_EQ(*shared, copy);
}

TEST(JpegEncoder, RejectsEmptyImages) {
  JpegEncoder encoder;
  EXPECT_THROW(encoder.encode(ImageRGB8{}), JpegError);
}

TEST(JpegDecoder, RejectsGarbageAndTruncatedData) {
  JpegDecoder decoder;
  const std::vector<std::uint8_t> garbage(100, 0x42);
  EXPECT_THROW(decoder.decode(garbage), JpegError);
  EXPECT_THROW(decoder.decode({}), JpegError);
  JpegEncoder encoder;
  const auto jpeg = encoder.encode(gradient_image(128, 128));
  const std::vector<std::uint8_t> truncated(jpeg.begin(), jpeg.begin() + jpeg.size() / 2);
  EXPECT_THROW(decoder.decode(truncated), JpegError);
}

}  // namespace
}  // namespace probeless
