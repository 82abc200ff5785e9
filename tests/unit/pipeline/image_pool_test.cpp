// The download stage's host images are reused only once every holder has let go
// (app/pipeline/image_pool.hpp).
#include "app/pipeline/image_pool.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <thread>
#include <vector>

namespace probeless {
namespace {

TEST(ImagePool, AnImageIsReusedOnlyOnceNobodyHoldsIt) {
  ImagePool<std::uint8_t, 3> pool(3);
  auto a = pool.take(4, 3);
  const auto* first = a.get();
  auto b = pool.take(4, 3);
  EXPECT_NE(b.get(), first) << "a held image is not handed out again";
  std::shared_ptr<const ImageRGB8> reader = a;  // an output keeps it (const, as they do)
  a.reset();
  EXPECT_NE(pool.take(4, 3).get(), first) << "still held by the reader";
  reader.reset();
  EXPECT_EQ(pool.take(4, 3).get(), first) << "free again: reused";
  EXPECT_EQ(pool.size(), 3u);
}

TEST(ImagePool, BeyondItsCapacityItAllocatesAndAfterAResizeItReplacesIdleImages) {
  ImagePool<float, 1> pool(2);
  std::vector<std::shared_ptr<ImageF>> held;
  for (int i = 0; i < 5; ++i) held.push_back(pool.take(8, 8));
  EXPECT_EQ(pool.size(), 2u);
  for (const auto& h : held) EXPECT_EQ(h->width(), 8);
  held.clear();
  auto resized = pool.take(16, 4);
  EXPECT_EQ(resized->width(), 16);
  EXPECT_EQ(resized->height(), 4);
  EXPECT_EQ(pool.size(), 2u);
  const auto* pooled = resized.get();
  resized.reset();
  EXPECT_EQ(pool.take(16, 4).get(), pooled) << "the new size is pooled";
}

// Holders on other threads (the outputs) let go while the owner takes: an image is never
// handed out while another thread still reads it.
TEST(ImagePool, ImagesReleasedOnOtherThreadsComeBack) {
  ImagePool<std::uint8_t, 3> pool(4);
  for (int round = 0; round < 200; ++round) {
    auto image = pool.take(8, 2);
    image->at(0, 0, 0) = static_cast<std::uint8_t>(round);
    std::shared_ptr<const ImageRGB8> reader = image;
    std::thread output([r = std::move(reader), round] {
      EXPECT_EQ(r->at(0, 0, 0), static_cast<std::uint8_t>(round));
    });
    image.reset();
    output.join();
  }
  EXPECT_LE(pool.size(), 4u);
}

}  // namespace
}  // namespace probeless
