#include "app/pipeline/light_pacing.hpp"

#include <gtest/gtest.h>

#include <array>

namespace probeless {
namespace {

// Frame i of a camera at `fps` running the four-frame bracket cycle L, M, H, M.
ExposureStamp bracketed(int i) {
  constexpr std::array<BracketLevel, 4> kLevels{BracketLevel::Low, BracketLevel::Medium,
                                                BracketLevel::High, BracketLevel::Medium};
  ExposureStamp e;
  e.cycle_position = static_cast<std::uint32_t>(i % 4);
  e.level = kLevels[e.cycle_position];
  e.cycle = static_cast<std::uint64_t>(i / 4);
  return e;
}

TimestampNs at(int i, double fps, double jitter_ms = 0) {
  return static_cast<TimestampNs>(i * 1e9 / fps + (i % 2 ? jitter_ms : -jitter_ms) * 1e6);
}

TEST(LightPacing, ZeroTakesEveryFrame) {
  LightPacing pacing(0);
  for (int i = 0; i < 100; ++i) EXPECT_TRUE(pacing.admit(bracketed(i), at(i, 50)));
  EXPECT_EQ(pacing.skipped(), 0u);
}

// 50 frames/s under a 25 Hz cap: every other cycle, whole, so each level keeps its share.
TEST(LightPacing, TakesWholeBracketCyclesAtTheCappedRate) {
  LightPacing pacing(25);
  std::array<int, 4> per_position{};
  int taken = 0;
  for (int i = 0; i < 400; ++i) {
    if (!pacing.admit(bracketed(i), at(i, 50, 1.5))) continue;
    ++taken;
    ++per_position[i % 4];
  }
  EXPECT_NEAR(taken, 200, 8);
  for (int p = 0; p < 4; ++p) EXPECT_EQ(per_position[p], taken / 4) << "cycle position " << p;
  EXPECT_EQ(pacing.skipped(), static_cast<std::uint64_t>(400 - taken));
}

// A camera only a little faster than the cap keeps nearly the cap's rate (the burst credit),
// and one slower than it loses nothing.
TEST(LightPacing, NearTheCapTheRateIsTheCapsNotHalfOfIt) {
  LightPacing at_30(25);
  int taken = 0;
  for (int i = 0; i < 600; ++i) taken += at_30.admit(bracketed(i), at(i, 30, 2.0));
  EXPECT_NEAR(taken / 20.0, 25.0, 1.5) << "frames a second of 20 s at 30 frames/s";
  LightPacing slower(25);
  for (int i = 0; i < 200; ++i) EXPECT_TRUE(slower.admit(bracketed(i), at(i, 20, 2.0)));
}

// Without bracketing (a fixed exposure) single frames are the unit.
TEST(LightPacing, FixedExposureFramesAreTakenOneByOne) {
  LightPacing pacing(25);
  ExposureStamp fixed;  // BracketLevel::Fixed, cycle 0 throughout
  int taken = 0, run = 0, longest_skip = 0;
  for (int i = 0; i < 500; ++i) {
    if (pacing.admit(fixed, at(i, 50, 1.0))) {
      ++taken;
      run = 0;
    } else {
      longest_skip = std::max(longest_skip, ++run);
    }
  }
  EXPECT_NEAR(taken, 250, 5);
  EXPECT_EQ(longest_skip, 1) << "every other frame, not in runs";
}

// A cycle whose first frames were dropped upstream is decided at the first frame that came.
TEST(LightPacing, ACycleIsDecidedAtItsFirstFrameThatArrives) {
  LightPacing pacing(25);
  EXPECT_TRUE(pacing.admit(bracketed(2), at(2, 50)));  // cycle 0 from its H frame
  EXPECT_TRUE(pacing.admit(bracketed(3), at(3, 50)));
  EXPECT_FALSE(pacing.admit(bracketed(4), at(4, 50)));  // cycle 1: no credit yet
  EXPECT_FALSE(pacing.admit(bracketed(7), at(7, 50)));
  EXPECT_TRUE(pacing.admit(bracketed(13), at(13, 50))) << "cycle 3, after 4 frames of credit";
}

}  // namespace
}  // namespace probeless
