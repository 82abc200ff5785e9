// The frame rate /status, the logs and systemd's STATUS= report.
#include <gtest/gtest.h>

#include <cstdint>

#include "base/stage_stats.hpp"

namespace probeless {
namespace {

constexpr std::int64_t kMs = 1'000'000;

// A steady stream, asked at every millisecond between two frames: the answer must not depend
// on where between the frames /status happens to be read.
void expect_steady_rate(std::int64_t period_ms, double expected_hz) {
  RateMeter meter;
  std::int64_t t = 0;
  for (int i = 0; i < 100; ++i, t += period_ms * kMs) meter.tick(t);
  const std::int64_t last = t - period_ms * kMs;
  for (std::int64_t q = last; q < last + period_ms * kMs; q += kMs)
    ASSERT_NEAR(meter.rate_hz(q), expected_hz, expected_hz * 0.01)
        << (q - last) / kMs << " ms after the last of frames " << period_ms << " ms apart";
}

TEST(RateMeter, SteadyStreamReadsTheSameBetweenFrames) {
  expect_steady_rate(33, 1000.0 / 33);
  expect_steady_rate(400, 2.5);  // the sim under ASan
  expect_steady_rate(900, 1000.0 / 900);
}

TEST(RateMeter, StoppedStreamReadsZeroAfterTheWindow) {
  RateMeter meter;
  for (std::int64_t t = 0; t <= 1000 * kMs; t += 100 * kMs) meter.tick(t);
  EXPECT_NEAR(meter.rate_hz(1500 * kMs), 10.0, 0.01);
  EXPECT_EQ(meter.rate_hz(2950 * kMs), 0.0);  // only the last tick is in the last 2 s
  EXPECT_EQ(RateMeter{}.rate_hz(0), 0.0);
}

}  // namespace
}  // namespace probeless
