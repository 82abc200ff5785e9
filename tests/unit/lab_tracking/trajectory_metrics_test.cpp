// The error measures of `eval tracking` on constructed trajectories whose errors are known.
#include "lab/eval/trajectory_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace probeless::eval {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();  // Eigen leaves {} uninitialised

Pose make_pose(const Eigen::Vector3d& axis_angle, const Eigen::Vector3d& t) {
  Pose p;
  if (axis_angle.norm() > 0)
    p.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(axis_angle.norm(), axis_angle.normalized()));
  p.translation = t;
  return p;
}

// A wandering hand-held-like trajectory at 30 fps: every axis moves, so no alignment is
// degenerate.
std::vector<PosePair> wandering_truth(int frames) {
  std::vector<PosePair> out;
  for (int i = 0; i < frames; ++i) {
    const double t = i / 30.0;
    const Pose truth = make_pose({0.3 * std::sin(t), 0.2 * std::cos(0.7 * t), 0.1 * t},
                                 {std::sin(t), 0.5 * std::cos(1.3 * t), 0.2 * t});
    out.push_back({static_cast<TimestampNs>(std::llround(t * 1e9)), truth, truth});
  }
  return out;
}

TEST(Umeyama, RecoversAKnownRigidMotion) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-2, 2);
  const Pose g = make_pose({0.4, -1.1, 0.7}, {0.3, -2.0, 1.5});
  std::vector<Eigen::Vector3d> src, dst;
  for (int i = 0; i < 20; ++i) {
    src.emplace_back(u(rng), u(rng), u(rng));
    dst.push_back(g * src.back());
  }
  const Pose found = umeyama_rigid(src, dst);
  EXPECT_LT((found.matrix() - g.matrix()).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Umeyama, RejectsTooFewOrMismatchedPoints) {
  const std::vector<Eigen::Vector3d> two(2, Eigen::Vector3d::Zero());
  const std::vector<Eigen::Vector3d> three(3, Eigen::Vector3d::Zero());
  EXPECT_THROW(umeyama_rigid(two, two), std::invalid_argument);
  EXPECT_THROW(umeyama_rigid(two, three), std::invalid_argument);
}

TEST(Ate, IsZeroForTheTruthSeenFromAnotherWorldFrame) {
  auto frames = wandering_truth(90);
  const Pose g = make_pose({1.0, 0.2, -0.5}, {3, -1, 0.5});  // another world origin
  for (auto& f : frames) f.estimate = g * *f.truth;
  const auto ate = ate_rmse_m(frames);
  ASSERT_TRUE(ate);
  EXPECT_LT(*ate, 1e-9);
}

TEST(Ate, FitsNoScale) {
  // Truth on a circle of 1 m, the estimate on a concentric circle of 1.1 m: by symmetry the
  // best rigid fit is the identity, so every position stays 0.1 m off (a similarity fit
  // would have made the error 0).
  std::vector<PosePair> frames;
  for (int i = 0; i < 60; ++i) {
    const double a = 2 * std::numbers::pi * i / 60;
    const Eigen::Vector3d dir(std::cos(a), std::sin(a), 0);
    frames.push_back({i * 33'000'000LL, make_pose(kZero, 1.1 * dir), make_pose(kZero, dir)});
  }
  EXPECT_NEAR(*ate_rmse_m(frames), 0.1, 1e-9);
}

TEST(Ate, SkipsFramesWithoutTruthAndNeedsThree) {
  auto frames = wandering_truth(5);
  frames[1].estimate.translation += Eigen::Vector3d(5, 5, 5);  // would dominate if counted
  frames[1].truth.reset();
  EXPECT_LT(*ate_rmse_m(frames), 1e-9);
  frames[0].truth.reset();
  frames[2].truth.reset();
  EXPECT_FALSE(ate_rmse_m(frames));
}

// 3 s at 30 fps: frames 0..90. Pairs (i, i + 30) for i = 0..59; from i = 60 on the closest
// frame to t_i + 1 s is the last one, which evaluate_rpe.py drops.
TEST(Rpe, TranslationDriftOfTenPercent) {
  std::vector<PosePair> frames;
  for (int i = 0; i <= 90; ++i) {
    const double t = i / 30.0;
    frames.push_back({static_cast<TimestampNs>(std::llround(t * 1e9)),
                      make_pose(kZero, {0.45 * t, 0, 0}), make_pose(kZero, {0.5 * t, 0, 0})});
  }
  const auto rpe = relative_pose_error(frames, 1.0);
  ASSERT_TRUE(rpe);
  EXPECT_EQ(rpe->pairs, 60);
  EXPECT_NEAR(rpe->translation_rmse_m, 0.05, 1e-9);
  EXPECT_NEAR(rpe->rotation_rmse_deg, 0.0, 1e-9);
}

TEST(Rpe, RotationDriftOfTwoDegreesPerSecond) {
  // The camera turns about its optical axis at 10 deg/s; the estimate at 12 deg/s.
  std::vector<PosePair> frames;
  for (int i = 0; i <= 90; ++i) {
    const double t = i / 30.0;
    frames.push_back({static_cast<TimestampNs>(std::llround(t * 1e9)),
                      make_pose({0, 0, 12 * kDeg * t}, kZero),
                      make_pose({0, 0, 10 * kDeg * t}, kZero)});
  }
  const auto rpe = relative_pose_error(frames, 1.0);
  ASSERT_TRUE(rpe);
  EXPECT_NEAR(rpe->rotation_rmse_deg, 2.0, 1e-6);
  EXPECT_NEAR(rpe->translation_rmse_m, 0.0, 1e-9);
}

TEST(Rpe, ExactTrackingHasNoErrorAndShortSequencesNoPairs) {
  const auto frames = wandering_truth(120);
  const auto rpe = relative_pose_error(frames, 1.0);
  ASSERT_TRUE(rpe);
  EXPECT_LT(rpe->translation_rmse_m, 1e-9);
  EXPECT_LT(rpe->rotation_rmse_deg, 1e-6);
  EXPECT_FALSE(relative_pose_error(wandering_truth(20), 1.0));  // 0.63 s: no 1 s pair
}

TEST(Registration, ACentimetreSidewaysAtTwoMetres) {
  // Truth: the camera does not move. Estimate: 1 cm to the right in frame 1. The anchored
  // point 2 m ahead then appears fx * 0.01 / 2 = 2.625 px to the left.
  const PinholeIntrinsics k;                                  // 640x480, f 525
  const Pose world = make_pose({0.3, 0.1, -0.2}, {1, 2, 3});  // the first pose is arbitrary
  std::vector<PosePair> frames{{0, world, world},
                               {1, world * make_pose(kZero, {0.01, 0, 0}), world}};
  const auto px = registration_px(frames, k, {0, 0, 2.0});
  ASSERT_EQ(px.size(), 2u);
  EXPECT_NEAR(px[0], 0.0, 1e-9);
  EXPECT_NEAR(px[1], 525 * 0.01 / 2, 1e-9);
}

TEST(Registration, AYawErrorAndOnlyFramesWhereTheTruthSeesThePoint) {
  const PinholeIntrinsics k;
  std::vector<PosePair> frames{
      {0, Pose::identity(), Pose::identity()},
      // The estimate turns 1 degree about the camera's y axis: the point moves by fx tan 1.
      {1, make_pose({0, 1 * kDeg, 0}, kZero), Pose::identity()},
      // The truth turns 90 degrees: the point is out of view, the frame does not count.
      {2, Pose::identity(), make_pose({0, 90 * kDeg, 0}, kZero)},
      // The estimate puts the point behind the camera: the image diagonal (800 px).
      {3, make_pose({0, 180 * kDeg, 0}, kZero), Pose::identity()}};
  const auto px = registration_px(frames, k, {0, 0, 1.5});
  ASSERT_EQ(px.size(), 3u);
  EXPECT_NEAR(px[1], 525 * std::tan(1 * kDeg), 1e-6);
  EXPECT_NEAR(px[2], 800.0, 1e-9);
  frames[0].truth.reset();
  EXPECT_THROW(registration_px(frames, k, {0, 0, 1.5}), std::invalid_argument);
}

TEST(Quantile, InterpolatesBetweenOrderStatistics) {
  EXPECT_DOUBLE_EQ(quantile({4, 1, 3, 2}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(quantile({4, 1, 3, 2}, 0.95), 3.85);
  EXPECT_DOUBLE_EQ(quantile({7}, 0.95), 7.0);
  EXPECT_DOUBLE_EQ(quantile({}, 0.5), 0.0);
}

}  // namespace
}  // namespace probeless::eval
