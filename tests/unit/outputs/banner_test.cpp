#include "app/outputs/banner.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace probeless {
namespace {

bool is_white(const ImageRGB8& image, int x, int y) {
  return image.at(x, y, 0) == 255 && image.at(x, y, 1) == 255 && image.at(x, y, 2) == 255;
}

// The bounding box of pixels of a given colour; width 0 when there are none.
Rect box_of_white(const ImageRGB8& image) {
  int x0 = image.width(), y0 = image.height(), x1 = -1, y1 = -1;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      if (!is_white(image, x, y)) continue;
      x0 = std::min(x0, x);
      y0 = std::min(y0, y);
      x1 = std::max(x1, x);
      y1 = std::max(y1, y);
    }
  }
  if (x1 < 0) return {};
  return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

TEST(Font, EveryPrintableGlyphButSpaceHasInk) {
  for (char c = ' '; c <= '_'; ++c) {
    const std::uint8_t* rows = glyph_rows(c);
    int ink = 0;
    for (int r = 0; r < kGlyphHeight; ++r) {
      EXPECT_EQ(rows[r] & ~0x1F, 0) << "glyph '" << c << "' wider than 5";
      ink += __builtin_popcount(rows[r]);
    }
    if (c == ' ') {
      EXPECT_EQ(ink, 0);
    } else {
      EXPECT_GT(ink, 0) << "glyph '" << c << "'";
    }
  }
  EXPECT_EQ(glyph_rows('a'), glyph_rows('A'));     // lower case drawn as capitals
  EXPECT_EQ(glyph_rows('~'), glyph_rows('?'));     // unknown as '?'
  EXPECT_EQ(glyph_rows('\x80'), glyph_rows('?'));  // and bytes beyond ASCII
  EXPECT_NE(glyph_rows('O'), glyph_rows('0'));
}

TEST(Font, TextMetrics) {
  EXPECT_EQ(text_width("", 3), 0);
  EXPECT_EQ(text_width("A", 1), 5);
  EXPECT_EQ(text_width("AB", 1), 11);
  EXPECT_EQ(text_width("AB", 3), 33);
  EXPECT_EQ(text_height(4), 28);
}

TEST(Font, DrawsTheGlyphPixelsScaledAndClipped) {
  ImageRGB8 image(20, 20);
  draw_text(image, 2, 3, "I", 2, {255, 255, 255});
  // 'I' = 0x0E on top: columns 1..3 of the cell, each 2x2 at scale 2.
  EXPECT_FALSE(is_white(image, 2, 3));
  EXPECT_TRUE(is_white(image, 4, 3));
  EXPECT_TRUE(is_white(image, 9, 4));
  EXPECT_FALSE(is_white(image, 10, 3));
  const Rect box = box_of_white(image);
  EXPECT_EQ(box.x, 4);
  EXPECT_EQ(box.y, 3);
  EXPECT_EQ(box.width, 6);
  EXPECT_EQ(box.height, 14);
  // Partly or wholly outside: clipped, no crash.
  draw_text(image, -7, -5, "HELLO WORLD", 3, {255, 255, 255});
  draw_text(image, 100, 100, "X", 1, {255, 255, 255});
}

TEST(Banner, NoSignalIsDrawnCentredAcrossTheMiddle) {
  ImageRGB8 image(640, 480, 200);  // a bright picture
  const Rect band = draw_no_signal(image, "rgbd", "stalled");
  // The band is a horizontal strip around the middle, not the whole picture.
  EXPECT_EQ(band.x, 0);
  EXPECT_EQ(band.width, 640);
  EXPECT_GT(band.height, 20);
  EXPECT_LT(band.height, 240);
  EXPECT_LT(band.y, 240);
  EXPECT_GT(band.y + band.height, 240);

  // Text pixels: inside the band, centred, and the title wide enough to read at a glance.
  const Rect text = box_of_white(image);
  ASSERT_GT(text.width, 0);
  EXPECT_GE(text.y, band.y);
  EXPECT_LE(text.y + text.height, band.y + band.height);
  EXPECT_NEAR(text.x + text.width / 2.0, 320, 6);
  EXPECT_GT(text.width, 640 / 3);

  // Outside the band the picture is dimmed, not replaced; inside it is the band colour.
  EXPECT_EQ(image.at(5, 5, 0), 100);
  EXPECT_EQ(image.at(5, band.y + 1, 1), 0);
}

TEST(Banner, DetailLinesAndFixedScale) {
  ImageRGB8 image(320, 240);
  BannerStyle style;
  style.title_scale = 2;
  style.dim_picture = false;
  style.band = {0, 0, 128};
  const std::vector<std::string> details = {"SOURCE: RGBD", "STATE: NO DEVICE"};
  const Rect band = draw_banner(image, "NO SIGNAL", details, style);
  const Rect text = box_of_white(image);
  EXPECT_EQ(text.width, text_width("STATE: NO DEVICE", 1) > text_width("NO SIGNAL", 2)
                            ? text_width("STATE: NO DEVICE", 1)
                            : text_width("NO SIGNAL", 2));
  EXPECT_GE(text.y, band.y);
  EXPECT_LE(text.y + text.height, band.y + band.height);
  EXPECT_EQ(image.at(1, band.y + 1, 2), 128);
  EXPECT_EQ(image.at(1, 1, 2), 0);  // not dimmed, untouched
}

TEST(Banner, TinyAndEmptyImagesDoNotCrash) {
  ImageRGB8 tiny(8, 6, 50);
  draw_no_signal(tiny, "a very long source name that cannot fit", "stalled");
  ImageRGB8 empty;
  EXPECT_EQ(draw_no_signal(empty, "x", "y").width, 0);
}

}  // namespace
}  // namespace probeless
