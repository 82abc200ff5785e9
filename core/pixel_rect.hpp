#pragma once
// A rectangle of pixels. The renderer finds where the virtual objects can be in a frame
// (app/render/screen_bounds.hpp); the per-pixel device stages after it work only there and
// around it (docs/architecture.md "Only the objects' pixels, end to end"): on the bench's
// orbit the objects cover 12-13 % of the frame on average.
#include <algorithm>

namespace probeless {

// The pixels [x0, x1) x [y0, y1) of an image, rows counted from the top; empty when either
// span is.
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  bool empty() const { return x1 <= x0 || y1 <= y0; }
  int width() const { return empty() ? 0 : x1 - x0; }
  int height() const { return empty() ? 0 : y1 - y0; }
  bool contains_row(int y) const { return !empty() && y >= y0 && y < y1; }
  bool contains(int x, int y) const { return contains_row(y) && x >= x0 && x < x1; }
  bool operator==(const PixelRect&) const = default;

  static PixelRect whole(int width, int height) { return {0, 0, width, height}; }
};

// The smallest rectangle holding both (an empty one holds nothing).
inline PixelRect unite(const PixelRect& a, const PixelRect& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

// The pixels in both.
inline PixelRect intersect(const PixelRect& a, const PixelRect& b) {
  const PixelRect r{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1),
                    std::min(a.y1, b.y1)};
  return r.empty() ? PixelRect{} : r;
}

// `r` widened by `margin` px on every side and clipped to a width x height image (a filter's
// reach around the pixels it must get right); empty stays empty.
inline PixelRect grown(const PixelRect& r, int margin, int width, int height) {
  if (r.empty()) return {};
  return intersect({r.x0 - margin, r.y0 - margin, r.x1 + margin, r.y1 + margin},
                   PixelRect::whole(width, height));
}

}  // namespace probeless
