#pragma once
// Text on frames with a built-in 5x7 bitmap font: the "NO SIGNAL" banner that the outputs
// draw over the last good frame when a source stops delivering (ustreamer's habit: show the
// fault in the picture rather than go silent), and small captions. No font files, no
// FreeType: an appliance must be able to say what is wrong with nothing else working.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "core/image.hpp"

namespace probeless {

struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
};

// The font: printable ASCII from ' ' to '_' (capitals, digits, punctuation); lower case is
// drawn as capitals and anything else as '?'. Cells are 5x7 pixels with one pixel between
// characters, times the integer scale.
inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 7;
// The rows of a glyph, top first, bit 4 = leftmost pixel.
const std::uint8_t* glyph_rows(char c);

int text_width(std::string_view text, int scale);
int text_height(int scale);
// Draws one line with its top-left corner at (x, y); clipped to the image.
void draw_text(ImageRGB8& image, int x, int y, std::string_view text, int scale, Rgb8 colour);

struct Rect {
  int x = 0, y = 0, width = 0, height = 0;
};

struct BannerStyle {
  int title_scale = 0;  // 0: as large as fits (about 80% of the width, 1/10 of the height)
  Rgb8 text{255, 255, 255};
  Rgb8 band{0, 0, 0};
  bool dim_picture = true;  // halve the picture's brightness so the banner reads as a state
};

// A band across the middle of the picture: the title large, each detail line a third of
// its size, all centred. Returns the band's rectangle (clipped to the image).
Rect draw_banner(ImageRGB8& image, std::string_view title,
                 std::span<const std::string> details = {}, const BannerStyle& style = {});

// "NO SIGNAL" over the picture, with "<source>: <state>" below it (e.g. "rgbd: stalled").
Rect draw_no_signal(ImageRGB8& image, std::string_view source, std::string_view state);

}  // namespace probeless
