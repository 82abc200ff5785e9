// count_exposure (eight pixels at a time) against count_exposure_per_pixel, the rule pixel by
// pixel: the counts are integers, so they must be equal, at every bit depth, black level and
// noise, for sizes that leave a tail of fewer than 8 pixels and one past the 16-bit counters'
// flush (more than 65535 groups of 8).
#include "core/exposure_count.hpp"

#include <gtest/gtest.h>

#include <random>

namespace probeless {
namespace {

ImageRGB16 random_raw(std::mt19937& rng, int w, int h, int bits, int black) {
  const int full = (1 << bits) - 1;
  std::uniform_int_distribution<int> any(0, full), pick(0, 9);
  ImageRGB16 raw(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        // Crowd the thresholds: full scale, the black level and their neighbours.
        const int k = pick(rng);
        const int v = k == 0   ? full
                      : k == 1 ? black
                      : k == 2 ? black + 1
                      : k == 3 ? full - 1
                               : any(rng);
        raw.at(x, y, c) = static_cast<std::uint16_t>(std::clamp(v, 0, full));
      }
  return raw;
}

TEST(ExposureCount, VectorLoopEqualsThePixelLoop) {
  std::mt19937 rng(5);
  struct Case {
    int w, h, bits, black;
    double read_noise, full_noise;
  };
  const Case cases[] = {{1, 1, 8, 16, 0, 0},
                        {7, 3, 8, 16, 0, 0},
                        {13, 11, 10, 64, 2.5, 4},
                        {640, 480, 12, 256, 3, 30},
                        {1024, 1024, 16, 4096, 8, 200},
                        {33, 9, 16, 0, 0, 0},
                        {17, 5, 1, 0, 0, 0},
                        {64, 64, 12, 256, 1e12, 1e12}};
  for (const Case& c : cases) {
    const ImageRGB16 raw = random_raw(rng, c.w, c.h, c.bits, c.black);
    const auto black = static_cast<std::uint16_t>(c.black);
    const ExposureStats want =
        count_exposure_per_pixel(raw, c.bits, black, c.read_noise, c.full_noise);
    const ExposureStats got = count_exposure(raw, c.bits, black, c.read_noise, c.full_noise);
    EXPECT_EQ(got, want) << c.w << "x" << c.h << " " << c.bits << " bits: saturated "
                         << got.saturated << "/" << want.saturated << ", zero " << got.zero << "/"
                         << want.zero << ", near saturated " << got.near_saturated << "/"
                         << want.near_saturated << ", near zero " << got.near_zero << "/"
                         << want.near_zero;
    EXPECT_GT(want.saturated + want.zero, 0u) << "the case tests nothing";
  }
}

}  // namespace
}  // namespace probeless
