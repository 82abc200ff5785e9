// The capture stamp (core/capture_stamp.hpp): what it writes reads back, clean and after the
// MJPEG stream's own coding (TurboJPEG q80, 4:2:0), and a stamp that is damaged or absent is
// rejected, never read as another time. H.264 is the latency bench's (bench_latency_cli_test).
#include "core/capture_stamp.hpp"

#include <gtest/gtest.h>

#include <random>

#include "app/outputs/jpeg_encoder.hpp"

namespace probeless {
namespace {

constexpr std::uint64_t kSpan = std::uint64_t{1} << 40;

// A busy scene: colour noise over gradients, the worst neighbour for the code's border.
ImageRGB8 scene(int width, int height, unsigned seed) {
  ImageRGB8 image(width, height);
  std::mt19937 rng(seed);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        image.at(x, y, c) = static_cast<std::uint8_t>((x * (c + 1) + y * (3 - c)) / 4 +
                                                      static_cast<int>(rng() % 96));
  return image;
}

ImageRGB8 through_jpeg(const ImageRGB8& image, int quality) {
  JpegEncoder encoder(quality);
  JpegDecoder decoder;
  return decoder.decode(encoder.encode(image));
}

TEST(CaptureStamp, ReadsBackWhatWasDrawn) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 50; ++i) {
    const auto t = static_cast<TimestampNs>(rng() >> 2);
    ImageRGB8 image = scene(640, 480, static_cast<unsigned>(i));
    ASSERT_TRUE(draw_capture_stamp(image, t));
    const StampReading r = read_capture_stamp(image);
    ASSERT_EQ(r.result, StampRead::Ok) << to_string(r.result);
    EXPECT_EQ(r.micros, static_cast<std::uint64_t>(t / 1000) % kSpan);
    EXPECT_EQ(unwrap_stamp(r.micros, t + ms_to_ns(40)), t / 1000 * 1000);
  }
}

TEST(CaptureStamp, OnlyTheCornerChanges) {
  const ImageRGB8 before = scene(640, 480, 1);
  ImageRGB8 after = before;
  draw_capture_stamp(after, 123456789);
  const CaptureStampLayout l = capture_stamp_layout(640, 480);
  EXPECT_EQ(l.cell_px, 8);
  EXPECT_EQ(l.x0 % 16, 0);
  EXPECT_EQ(l.y0 % 16, 0);
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) {
      const bool in_box = x >= l.x0 - l.cell_px && x < l.x0 + l.width() + l.cell_px &&
                          y >= l.y0 - l.cell_px && y < l.y0 + l.height() + l.cell_px;
      if (!in_box) {
        ASSERT_EQ(before.at(x, y, 1), after.at(x, y, 1)) << x << "," << y;
      }
    }
  EXPECT_LT(l.x0 + l.width(), 640 / 3) << "the code stays in the corner";
  EXPECT_GT(l.y0, 480 * 3 / 4);
}

TEST(CaptureStamp, SurvivesJpegAtTheStreamsQuality) {
  std::mt19937_64 rng(11);
  for (const auto& [w, h] :
       {std::pair{640, 480}, std::pair{1280, 720}, std::pair{1920, 1080}, std::pair{320, 240}}) {
    for (int i = 0; i < 8; ++i) {
      const auto t = static_cast<TimestampNs>(rng() >> 2);
      ImageRGB8 image = scene(w, h, static_cast<unsigned>(i));
      ASSERT_TRUE(draw_capture_stamp(image, t));
      for (int quality : {80, 50}) {
        const StampReading r = read_capture_stamp(through_jpeg(image, quality));
        ASSERT_EQ(r.result, StampRead::Ok)
            << w << "x" << h << " q" << quality << " " << to_string(r.result);
        EXPECT_EQ(r.micros, static_cast<std::uint64_t>(t / 1000) % kSpan);
      }
    }
  }
}

// Every single cell drawn the wrong way (a misread the threshold cannot see) is caught by the
// guard or the CRC; so is every pair of payload cells (CRC-16 finds all two-bit errors).
TEST(CaptureStamp, AWrongCellIsRejectedNotReadAsAnotherTime) {
  const ImageRGB8 base = scene(640, 480, 3);
  ImageRGB8 stamped = base;
  draw_capture_stamp(stamped, 987654321000);
  const CaptureStampLayout l = capture_stamp_layout(640, 480);
  const auto flip = [&](ImageRGB8& image, int cell) {
    const int cx = l.x0 + cell % 16 * l.cell_px, cy = l.y0 + cell / 16 * l.cell_px;
    for (int y = cy; y < cy + l.cell_px; ++y)
      for (int x = cx; x < cx + l.cell_px; ++x)
        for (int c = 0; c < 3; ++c) image.at(x, y, c) = 255 - image.at(x, y, c);
  };
  for (int a = 0; a < 64; ++a) {
    ImageRGB8 one = stamped;
    flip(one, a);
    EXPECT_NE(read_capture_stamp(one).result, StampRead::Ok) << "cell " << a;
    for (int b = std::max(a + 1, 8); b < 64; ++b) {
      ImageRGB8 two = one;
      flip(two, b);
      ASSERT_NE(read_capture_stamp(two).result, StampRead::Ok) << "cells " << a << ", " << b;
    }
  }
  // A grey cell is not guessed.
  ImageRGB8 grey = stamped;
  const int cx = l.x0 + 20 % 16 * l.cell_px, cy = l.y0 + 20 / 16 * l.cell_px;
  for (int y = cy; y < cy + l.cell_px; ++y)
    for (int x = cx; x < cx + l.cell_px; ++x)
      for (int c = 0; c < 3; ++c) grey.at(x, y, c) = 128;
  EXPECT_EQ(read_capture_stamp(grey).result, StampRead::Ambiguous);
}

TEST(CaptureStamp, NoStampIsNotRead) {
  EXPECT_NE(read_capture_stamp(scene(640, 480, 5)).result, StampRead::Ok);
  EXPECT_EQ(read_capture_stamp(ImageRGB8(640, 480, 255)).result, StampRead::LowContrast);
  EXPECT_EQ(read_capture_stamp(ImageRGB8(640, 480, 0)).result, StampRead::LowContrast);
  // Random pictures: 64 cells of noise pass the guard and the CRC about once in 2^24.
  std::mt19937 rng(9);
  int read = 0;
  for (int i = 0; i < 100; ++i) {
    ImageRGB8 noise(320, 240);
    for (auto& v : noise.elements()) v = static_cast<std::uint8_t>(rng() & 0x80 ? 255 : 0);
    read += read_capture_stamp(noise).result == StampRead::Ok;
  }
  EXPECT_EQ(read, 0);
}

TEST(CaptureStamp, TooSmallAnImageHasNoStamp) {
  ImageRGB8 tiny(96, 48);
  EXPECT_FALSE(draw_capture_stamp(tiny, 1000));
  EXPECT_EQ(tiny, ImageRGB8(96, 48));
  EXPECT_EQ(read_capture_stamp(tiny).result, StampRead::TooSmall);
}

TEST(CaptureStamp, UnwrapsAcrossTheWrap) {
  const TimestampNs span_ns = static_cast<TimestampNs>(kSpan) * 1000;
  const TimestampNs t = 5 * span_ns - 3'000'000;  // 3 ms before a wrap of the 40 bits
  const std::uint64_t micros = static_cast<std::uint64_t>(t / 1000) % kSpan;
  EXPECT_EQ(unwrap_stamp(micros, t + ms_to_ns(50)), t);  // the receiver is past the wrap
  EXPECT_EQ(unwrap_stamp(micros, t - ms_to_ns(50)), t);  // a receiver behind it
  EXPECT_EQ(unwrap_stamp(micros, t), t);
}

TEST(CaptureStamp, CrcIsCcittFalse) {
  // The payload's bytes least significant first, 01 02 03 04 05; the value from Python's
  // binascii.crc_hqx(bytes([1, 2, 3, 4, 5]), 0xFFFF), an independent CRC-16/CCITT-FALSE.
  EXPECT_EQ(capture_stamp_crc(0x0504030201), 0x9304);
}

}  // namespace
}  // namespace probeless
