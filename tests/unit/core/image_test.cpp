// Image's invariant: width * height * channels elements, also after a move.
#include "core/image.hpp"

#include <gtest/gtest.h>

#include <utility>

namespace probeless {
namespace {

// A moved-from image used to keep its size with no pixels, and a source that reuses a frame
// whose size matches (SimFisheyeSource::expose after `pending = std::move(frame)` in the
// record command) wrote rows into a null buffer.
TEST(Image, MovedFromImageIsEmpty) {
  ImageRGB16 a(4, 3, 7);
  ImageRGB16 b(std::move(a));
  EXPECT_EQ(b.width(), 4);
  EXPECT_EQ(b.at(3, 2, 2), 7);
  EXPECT_EQ(a.width(), 0);   // NOLINT(bugprone-use-after-move): the state is what is tested
  EXPECT_EQ(a.height(), 0);  // NOLINT(bugprone-use-after-move)
  EXPECT_TRUE(a.empty());    // NOLINT(bugprone-use-after-move)

  ImageRGB16 c(2, 2);
  c = std::move(b);
  EXPECT_EQ(c.width(), 4);
  EXPECT_EQ(b.pixel_count(), 0u);   // NOLINT(bugprone-use-after-move)
  EXPECT_EQ(b.row_elements(), 0u);  // NOLINT(bugprone-use-after-move)
  b = ImageRGB16(1, 1);             // a moved-from image is usable again
  EXPECT_EQ(b.size_bytes(), 6u);
}

TEST(Image, CopyKeepsTheSource) {
  const ImageRGB8 a(2, 1, 9);
  ImageRGB8 b = a;
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.width(), 2);
}

}  // namespace
}  // namespace probeless
