#include "kernels/hdr/exposure_count.hpp"

#include <gtest/gtest.h>

#include <random>

#include "support/cl_context.hpp"

namespace probeless {
namespace {

using testing::cl_context;

// Values clustered around every threshold: black level, just above it, half scale, full.
ImageRGB16 raw_near_thresholds(int w, int h, int bits, std::uint16_t black, unsigned seed) {
  std::mt19937 rng(seed);
  const int white = (1 << bits) - 1;
  const int range = white - black;
  const int anchors[] = {0, black, black + 1, black + 4, black + range / 2, white - 8, white};
  std::uniform_int_distribution<int> pick(0, 6), jitter(-6, 6), any(0, white);
  ImageRGB16 raw(w, h);
  for (auto& v : raw.elements()) {
    const int a = anchors[pick(rng)];
    v = static_cast<std::uint16_t>(
        std::clamp(pick(rng) == 0 ? any(rng) : a + jitter(rng), 0, white));
  }
  return raw;
}

TEST(ExposureCount, MatchesTheCpuCountOnEverySize) {
  auto& ctx = cl_context();
  ExposureCount counter(ctx);
  auto sizes = testing::kernel_test_sizes();
  sizes.emplace_back(1024, 1024);  // the fisheye's size: more pixels than work-items
  unsigned seed = 1;
  for (const int bits : {8, 12}) {
    const std::uint16_t black = bits == 8 ? 16 : 256;
    for (const auto& [w, h] : sizes) {
      const auto host = raw_near_thresholds(w, h, bits, black, seed++);
      const DeviceImage<std::uint16_t, 3> raw(ctx, host);
      for (const auto& [read_noise, full_noise] :
           {std::pair{0.0, 0.0}, std::pair{0.3, 2.0}, std::pair{1.2, 25.5}}) {
        const ExposureStats expected = count_exposure(host, bits, black, read_noise, full_noise);
        EXPECT_EQ(counter.count(raw, bits, black, read_noise, full_noise), expected)
            << w << "x" << h << " " << bits << " bit, noise " << read_noise << "/" << full_noise;
        if (w * h > 1000) {  // the frames reach every count
          EXPECT_GT(expected.saturated, 0u);
          EXPECT_GT(expected.zero, 0u);
          EXPECT_GT(expected.near_saturated, expected.saturated);
          EXPECT_GT(expected.near_zero, expected.zero);
        }
      }
    }
  }
}

TEST(ExposureCount, EmptyFrameAndBadInput) {
  auto& ctx = cl_context();
  ExposureCount counter(ctx);
  const DeviceImage<std::uint16_t, 3> empty;
  EXPECT_EQ(counter.count(empty, 12, 256), ExposureStats{});
  const DeviceImage<std::uint16_t, 3> raw(ctx, ImageRGB16(3, 3, 50));
  EXPECT_THROW(counter.count(raw, 8, 255), std::invalid_argument);
  EXPECT_THROW(counter.count(raw, 0, 0), std::invalid_argument);
  EXPECT_THROW(counter.count(raw, 17, 0), std::invalid_argument);
}

// The integer thresholds say what the double limits of count_exposure's contract say.
TEST(ExposureThresholds, AgreeWithTheDocumentedLimits) {
  // 8 bit, black 16: range 239. 2 s >= 239 - 3 * 2.0 = 233  <=>  s >= 117.
  const auto t = exposure_thresholds(8, 16, 0.3, 2.0);
  EXPECT_EQ(t.saturated_signal, 239);
  EXPECT_EQ(t.zero_signal, 0);
  EXPECT_EQ(t.near_saturated_signal, 117);
  EXPECT_EQ(t.near_zero_signal, 2);  // s <= 1 + 1.8
  const auto q = exposure_thresholds(8, 16);
  EXPECT_EQ(q.near_saturated_signal, 120);  // 2 s >= 239
  EXPECT_EQ(q.near_zero_signal, 1);
}

}  // namespace
}  // namespace probeless
