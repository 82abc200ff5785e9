// The bracket sequencer's decisions on hand-made counts, the mains limit and the gain/time
// split (docs/bracketing.md).
#include "drivers/bracket/bracket_sequencer.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace probeless {
namespace {

constexpr std::size_t kPixels = 1000000;
// Low: 2e-5 -> 20 pixels; medium's bulk and high: 0.001 -> 1000 pixels.
constexpr std::size_t kLowLimit = 20;

// The stamp the sequencer would give a level now (the cycle is only read by the medium rule).
ExposureStamp stamp_for(const BracketSequencer& seq, BracketLevel level, std::uint64_t cycle = 0) {
  const int stop = level == BracketLevel::Low    ? seq.low_stop()
                   : level == BracketLevel::High ? seq.high_stop()
                                                 : seq.medium_stop();
  ExposureStamp s;
  s.level = level;
  s.cycle = cycle;
  s.cycle_position = level == BracketLevel::Low ? 0 : level == BracketLevel::High ? 2 : 3;
  s.exposure = split_exposure(seq.exposure_value(stop), seq.config());
  return s;
}

TEST(BracketSequencer, StartsThreeStopsApartWithinTheCameraRange) {
  BracketSequencer seq;  // E0 = 5 ms; E from 10 us to 20 ms x 24 dB = 0.317
  EXPECT_EQ(seq.low_stop(), -3);
  EXPECT_EQ(seq.medium_stop(), 0);
  EXPECT_EQ(seq.high_stop(), 3);
  EXPECT_EQ(seq.min_stop(), -8);
  EXPECT_EQ(seq.max_stop(), 5);
}

TEST(BracketSequencer, CyclesLowMediumHighMediumWithStamps) {
  BracketSequencer seq;
  const BracketLevel order[4] = {BracketLevel::Low, BracketLevel::Medium, BracketLevel::High,
                                 BracketLevel::Medium};
  for (int i = 0; i < 8; ++i) {
    const ExposureStamp s = seq.next();
    EXPECT_EQ(s.level, order[i % 4]) << i;
    EXPECT_EQ(s.cycle_position, static_cast<std::uint32_t>(i % 4));
    EXPECT_EQ(s.cycle, static_cast<std::uint64_t>(i / 4));
    if (s.level == BracketLevel::Low) {
      EXPECT_DOUBLE_EQ(s.exposure.time_s, 0.005 / 8);
      EXPECT_DOUBLE_EQ(s.exposure.gain_db, 0.0);
    } else if (s.level == BracketLevel::Medium) {
      EXPECT_DOUBLE_EQ(s.exposure.time_s, 0.005);
      EXPECT_DOUBLE_EQ(s.exposure.gain_db, 0.0);
    } else {  // 40 ms: 20 ms (one 50 Hz period) at x2 = 6.02 dB
      EXPECT_DOUBLE_EQ(s.exposure.time_s, 0.02);
      EXPECT_NEAR(s.exposure.gain_db, 6.0206, 1e-4);
      EXPECT_NEAR(s.exposure.value(), 0.04, 1e-12);
    }
  }
}

TEST(BracketSequencer, LowStepsDownWhileTooManySaturate) {
  BracketSequencer seq;
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::Low), {kPixels, kLowLimit + 1, 0}));
  EXPECT_EQ(seq.low_stop(), -4);
  // At the threshold (not above) and some saturated: stay.
  EXPECT_FALSE(seq.observe(stamp_for(seq, BracketLevel::Low), {kPixels, kLowLimit, 0}));
  EXPECT_EQ(seq.low_stop(), -4);
  // Never below the camera's shortest exposure.
  for (int i = 0; i < 10; ++i)
    seq.observe(stamp_for(seq, BracketLevel::Low), {kPixels, kPixels, 0});
  EXPECT_EQ(seq.low_stop(), seq.min_stop());
}

TEST(BracketSequencer, LowStepsUpWhenNoneSaturateKeepingOneStopBelowMedium) {
  BracketSequencer seq;
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::Low), {kPixels, 0, 0}));
  EXPECT_EQ(seq.low_stop(), -2);
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::Low), {kPixels, 0, 0}));
  EXPECT_EQ(seq.low_stop(), -1);
  EXPECT_FALSE(seq.observe(stamp_for(seq, BracketLevel::Low), {kPixels, 0, 0}));
  EXPECT_EQ(seq.low_stop(), -1);  // M is 0: at least one stop between them
}

TEST(BracketSequencer, LowDoesNotStepUpIntoAnExposureThatWouldSaturate) {
  BracketSequencer seq;
  ExposureStats stats{kPixels, 0, 0};
  stats.near_saturated = kLowLimit + 1;  // one stop more would saturate too many
  EXPECT_FALSE(seq.observe(stamp_for(seq, BracketLevel::Low), stats));
  EXPECT_EQ(seq.low_stop(), -3);
  stats.near_saturated = kLowLimit;
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::Low), stats));
  EXPECT_EQ(seq.low_stop(), -2);
}

TEST(BracketSequencer, HighStepsUpOnZerosAndDownWhenNone) {
  BracketSequencer seq;
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::High), {kPixels, 0, 1001}));
  EXPECT_EQ(seq.high_stop(), 4);
  EXPECT_FALSE(seq.observe(stamp_for(seq, BracketLevel::High), {kPixels, 0, 1000}));
  EXPECT_EQ(seq.high_stop(), 4);
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::High), {kPixels, 0, 1001}));
  EXPECT_EQ(seq.high_stop(), 5);
  EXPECT_FALSE(seq.observe(stamp_for(seq, BracketLevel::High), {kPixels, 0, kPixels}));
  EXPECT_EQ(seq.high_stop(), 5);  // the camera's longest time at its highest gain
  for (int i = 0; i < 10; ++i) seq.observe(stamp_for(seq, BracketLevel::High), {kPixels, 0, 0});
  EXPECT_EQ(seq.high_stop(), 1);  // one stop above M
  ExposureStats stats{kPixels, 0, 0};
  BracketSequencer fresh;
  stats.near_zero = 1001;  // one stop less would zero too many
  EXPECT_FALSE(fresh.observe(stamp_for(fresh, BracketLevel::High), stats));
  EXPECT_EQ(fresh.high_stop(), 3);
}

TEST(BracketSequencer, IgnoresStaleAndFixedFrames) {
  BracketSequencer seq;
  const ExposureStamp old = stamp_for(seq, BracketLevel::Low);
  EXPECT_TRUE(seq.observe(old, {kPixels, kPixels, 0}));
  EXPECT_FALSE(seq.observe(old, {kPixels, kPixels, 0}));  // taken before the step: ignored
  EXPECT_EQ(seq.low_stop(), -4);
  ExposureStamp fixed = stamp_for(seq, BracketLevel::Low);
  fixed.level = BracketLevel::Fixed;
  EXPECT_FALSE(seq.observe(fixed, {kPixels, kPixels, 0}));
}

TEST(BracketSequencer, MediumMovesSlowlyTowardsTheMiddle) {
  BracketSequencer seq;
  for (int i = 0; i < 5; ++i) seq.observe(stamp_for(seq, BracketLevel::Low), {kPixels, kPixels, 0});
  ASSERT_EQ(seq.low_stop(), -8);  // L -8, H 3: middle -3 (rounded down)
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::Medium, 0), {kPixels, 0, 0}));
  EXPECT_EQ(seq.medium_stop(), -1);
  EXPECT_FALSE(seq.observe(stamp_for(seq, BracketLevel::Medium, 1), {kPixels, 0, 0}));
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::Medium, 2), {kPixels, 0, 0}));
  EXPECT_EQ(seq.medium_stop(), -2);
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::Medium, 4), {kPixels, 0, 0}));
  EXPECT_FALSE(seq.observe(stamp_for(seq, BracketLevel::Medium, 6), {kPixels, 0, 0}));
  EXPECT_EQ(seq.medium_stop(), -3);
  // The first medium frame of a cycle never moves it.
  ExposureStamp first = stamp_for(seq, BracketLevel::Medium, 10);
  first.cycle_position = 1;
  EXPECT_FALSE(seq.observe(first, {kPixels, 0, 0}));

  BracketConfig fixed_config;
  fixed_config.adapt_medium = false;
  BracketSequencer fixed(fixed_config);
  for (int i = 0; i < 5; ++i)
    fixed.observe(stamp_for(fixed, BracketLevel::Low), {kPixels, kPixels, 0});
  EXPECT_FALSE(fixed.observe(stamp_for(fixed, BracketLevel::Medium, 0), {kPixels, 0, 0}));
  EXPECT_EQ(fixed.medium_stop(), 0);
}

// L goes down for the few brightest pixels (the light's energy), M stays placed by the bulk
// of the scene: the highest L stop seen with at most 0.001 saturated.
TEST(BracketSequencer, MediumFollowsTheBulkNotTheBrightestFewPixels) {
  BracketSequencer seq;
  const std::size_t seen[] = {5000, 500, 100, 10};  // at stops -3, -4, -5, -6
  for (const std::size_t saturated : seen)
    seq.observe(stamp_for(seq, BracketLevel::Low), {kPixels, saturated, 0});
  ASSERT_EQ(seq.low_stop(), -6);
  EXPECT_EQ(seq.bulk_low_stop(), -4);
  // Towards floor((-4 + 3) / 2) = -1, not floor((-6 + 3) / 2) = -2.
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::Medium, 0), {kPixels, 0, 0}));
  EXPECT_EQ(seq.medium_stop(), -1);
  EXPECT_FALSE(seq.observe(stamp_for(seq, BracketLevel::Medium, 2), {kPixels, 0, 0}));
  EXPECT_EQ(seq.medium_stop(), -1);

  // The scene brightens: what was seen at the longer stops no longer holds.
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::Low), {kPixels, 2000, 0}));
  EXPECT_EQ(seq.low_stop(), -7);
  EXPECT_EQ(seq.bulk_low_stop(), -7);  // nothing known to hold the bulk: L itself
  EXPECT_FALSE(seq.observe(stamp_for(seq, BracketLevel::Low), {kPixels, 5, 0}));
  EXPECT_EQ(seq.bulk_low_stop(), -7);
  EXPECT_TRUE(seq.observe(stamp_for(seq, BracketLevel::Medium, 4), {kPixels, 0, 0}));
  EXPECT_EQ(seq.medium_stop(), -2);  // towards floor((-7 + 3) / 2)
}

TEST(SplitExposure, LongestTimeUpToTheMainsPeriodThenLowestGain) {
  BracketConfig c;  // 50 Hz: 20 ms
  EXPECT_DOUBLE_EQ(max_integration_time(c), 0.02);
  Exposure e = split_exposure(0.01, c);
  EXPECT_DOUBLE_EQ(e.time_s, 0.01);
  EXPECT_DOUBLE_EQ(e.gain_db, 0.0);
  e = split_exposure(0.02, c);
  EXPECT_DOUBLE_EQ(e.time_s, 0.02);
  EXPECT_DOUBLE_EQ(e.gain_db, 0.0);
  e = split_exposure(0.08, c);  // x4 = 12.04 dB
  EXPECT_DOUBLE_EQ(e.time_s, 0.02);
  EXPECT_NEAR(e.gain_db, 12.0412, 1e-4);
  EXPECT_NEAR(e.value(), 0.08, 1e-12);

  c.mains_hz = 60;  // 16.7 ms
  EXPECT_NEAR(max_integration_time(c), 1.0 / 60, 1e-15);
  e = split_exposure(0.05, c);  // x3 = 9.54 dB
  EXPECT_NEAR(e.time_s, 0.0166667, 1e-7);
  EXPECT_NEAR(e.gain_db, 9.5424, 1e-4);
  EXPECT_NEAR(e.value(), 0.05, 1e-12);
  e = split_exposure(0.016, c);
  EXPECT_DOUBLE_EQ(e.time_s, 0.016);
  EXPECT_DOUBLE_EQ(e.gain_db, 0.0);
}

TEST(SplitExposure, ClampsToTheCamera) {
  BracketConfig c;
  c.max_time_s = 0.01;  // the camera's own limit is below the mains period
  EXPECT_DOUBLE_EQ(max_integration_time(c), 0.01);
  Exposure e = split_exposure(0.02, c);
  EXPECT_DOUBLE_EQ(e.time_s, 0.01);
  EXPECT_NEAR(e.gain_db, 6.0206, 1e-4);
  e = split_exposure(10.0, c);  // beyond 24 dB
  EXPECT_DOUBLE_EQ(e.gain_db, 24.0);
  e = split_exposure(1e-7, c);  // below the shortest time
  EXPECT_DOUBLE_EQ(e.time_s, 1e-5);
  EXPECT_DOUBLE_EQ(e.gain_db, 0.0);
  c.mains_hz = 0;  // no mains limit
  c.max_time_s = 0.1;
  EXPECT_DOUBLE_EQ(split_exposure(0.05, c).time_s, 0.05);
}

TEST(CountExposure, CountsHandMadePixels) {
  // 8 bits, black 16: full scale 255, signal range 239.
  ImageRGB16 raw(6, 1);
  const std::uint16_t px[6][3] = {
      {255, 100, 100},  // saturated (and near)
      {16, 100, 100},   // zero (and near zero)
      {17, 100, 100},   // near zero: 1 DN of signal
      {136, 40, 40},    // near saturated: 2 * 120 >= 239
      {135, 40, 40},    // neither: 2 * 119 < 239
      {0, 255, 10},     // both saturated and zero (below black)
  };
  for (int x = 0; x < 6; ++x)
    for (int c = 0; c < 3; ++c) raw.at(x, 0, c) = px[x][c];
  const ExposureStats s = count_exposure(raw, 8, 16);
  EXPECT_EQ(s.pixels, 6u);
  EXPECT_EQ(s.saturated, 2u);
  EXPECT_EQ(s.zero, 2u);
  EXPECT_EQ(s.near_saturated, 3u);
  EXPECT_EQ(s.near_zero, 3u);
  EXPECT_THROW(count_exposure(raw, 8, 255), std::invalid_argument);
}

}  // namespace
}  // namespace probeless
