// The rig poses the light thread looks up at fisheye timestamps (app/pipeline/pose_history).
#include "app/pipeline/pose_history.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace probeless {
namespace {

constexpr TimestampNs kMs = 1'000'000;

Pose at_x(double x, double yaw_deg = 0) {
  Pose p;
  p.translation = Eigen::Vector3d(x, 0, 0);
  p.rotation = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitZ());
  return p;
}

double yaw_deg(const Pose& p) {
  return Eigen::AngleAxisd(p.rotation).angle() * 180 / M_PI;
}

TEST(PoseHistory, InterpolatesLinearlyAndBySlerpBetweenSamples) {
  PoseHistory h;
  h.add(100 * kMs, at_x(0.0, 0));
  h.add(133 * kMs, at_x(0.33, 30));
  const auto p = h.at(111 * kMs);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->translation.x(), 0.11, 1e-9);
  EXPECT_NEAR(yaw_deg(*p), 10.0, 1e-6);
  EXPECT_NEAR(h.at(133 * kMs)->translation.x(), 0.33, 1e-12);
}

TEST(PoseHistory, HoldsTheEndsOnlyWithinTheBound) {
  PoseHistory h(50 * kMs);
  h.add(100 * kMs, at_x(1));
  h.add(133 * kMs, at_x(2));
  EXPECT_NEAR(h.at(180 * kMs)->translation.x(), 2, 1e-12);  // 47 ms past the newest
  EXPECT_FALSE(h.at(184 * kMs));                            // 51 ms
  EXPECT_NEAR(h.at(60 * kMs)->translation.x(), 1, 1e-12);
  EXPECT_FALSE(h.at(40 * kMs));
  EXPECT_FALSE(PoseHistory().at(0));
}

TEST(PoseHistory, NeverInterpolatesAcrossALossOrALongGap) {
  PoseHistory h(10 * kMs, 250 * kMs);
  h.add(100 * kMs, at_x(1));
  h.mark_unknown(133 * kMs);
  h.add(166 * kMs, at_x(3));
  EXPECT_FALSE(h.at(120 * kMs));  // between a pose and a loss, 20 ms from the pose
  EXPECT_NEAR(h.at(105 * kMs)->translation.x(), 1, 1e-12);  // within the hold
  EXPECT_FALSE(h.at(133 * kMs));
  EXPECT_FALSE(h.at(150 * kMs));
  h.add(500 * kMs, at_x(4));  // 334 ms after the last: the motion between is not known
  EXPECT_FALSE(h.at(300 * kMs));
}

TEST(PoseHistory, OlderSamplesAreIgnoredAndTheOldestDropped) {
  PoseHistory h(0, 250 * kMs, 4);
  for (int i = 0; i < 6; ++i) h.add(i * 10 * kMs, at_x(i));
  h.add(20 * kMs, at_x(99));
  EXPECT_EQ(h.size(), 4u);
  EXPECT_FALSE(h.at(10 * kMs));
  EXPECT_NEAR(h.at(45 * kMs)->translation.x(), 4.5, 1e-12);
}

TEST(PoseHistory, WaitsForTheWriterToCatchUp) {
  PoseHistory h;
  h.add(0, at_x(0));
  std::jthread writer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    h.add(100 * kMs, at_x(1));
  });
  // 60 ms is past the hold: only the sample the writer brings answers it.
  const auto p = h.wait_at(60 * kMs, std::chrono::milliseconds(2000));
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->translation.x(), 0.6, 1e-9);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(h.wait_at(900 * kMs, std::chrono::milliseconds(30)));
  EXPECT_GE(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(30));
}

TEST(PoseHistory, BadParametersThrow) {
  EXPECT_THROW(PoseHistory(-1), std::invalid_argument);
  EXPECT_THROW(PoseHistory(0, 0), std::invalid_argument);
  EXPECT_THROW(PoseHistory(0, 1, 1), std::invalid_argument);
}

}  // namespace
}  // namespace probeless
