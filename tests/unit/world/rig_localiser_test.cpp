// T_world_rig = T_world_tracker * T_tracker_camera * T_rgb_rig for each [tracking] method and
// [world] anchor, on synthetic frames (app/world/rig_localiser).
#include "app/world/rig_localiser.hpp"

#include <gtest/gtest.h>

namespace probeless::world {
namespace {

RigCalibration calibration() {
  RigCalibration c;
  c.rgb = PinholeCamera(PinholeIntrinsics{});
  Eigen::Matrix3d r;  // the sim's colour camera in the rig: forward = rig y, down = -rig z
  r << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  c.T_rig_rgb.rotation = Eigen::Quaterniond(r);
  c.T_rig_rgb.translation = Eigen::Vector3d(0.01, 0.02, 0.03);
  return c;
}

RgbdFrame frame_at(const Pose& T_world_rig, std::uint64_t sequence) {
  RgbdFrame f;
  f.sequence = sequence;
  f.timestamp_ns = static_cast<TimestampNs>(sequence) * 33'000'000;
  f.colour = ImageRGB8(640, 480);
  f.depth = DepthImage(640, 480);
  auto truth = std::make_shared<FrameTruth>();
  truth->rig_pose = T_world_rig;
  f.truth = truth;
  return f;
}

Pose rig_at(double x, double yaw_deg) {
  Pose p;
  p.translation = Eigen::Vector3d(x, 0.5, 1.2);
  p.rotation = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitZ());
  return p;
}

void expect_same(const Pose& a, const Pose& b) {
  EXPECT_LT((a.translation - b.translation).norm(), 1e-9);
  EXPECT_LT(a.rotation.angularDistance(b.rotation), 1e-9);
}

TEST(RigLocaliser, TruthInTheRigsWorldIsTheSourcesPose) {
  TrackingConfig t;
  t.method = "truth";
  RigLocaliser loc(t, WorldConfig{}, calibration(), nullptr);
  for (int i = 0; i < 3; ++i) {
    const auto p = loc.locate(frame_at(rig_at(0.1 * i, 10.0 * i), i));
    ASSERT_TRUE(p);
    expect_same(*p, rig_at(0.1 * i, 10.0 * i));
  }
  EXPECT_EQ(loc.status().state, tracking::TrackingState::Tracking);
  EXPECT_TRUE(loc.status().anchor_found);
  const nlohmann::json j = loc.status().to_json();
  EXPECT_EQ(j["method"], "truth");
  EXPECT_EQ(j["anchor"]["kind"], "rig");
  EXPECT_NEAR(j["pose"]["t"][0].get<double>(), 0.2, 1e-9);
  EXPECT_EQ(j["pose"]["q"].size(), 4u);
}

TEST(RigLocaliser, AFrameWithoutTruthIsLostAndCounted) {
  TrackingConfig t;
  t.method = "truth";
  RigLocaliser loc(t, WorldConfig{}, calibration(), nullptr);
  ASSERT_TRUE(loc.locate(frame_at(rig_at(0, 0), 0)));
  RgbdFrame blind = frame_at(rig_at(0, 0), 1);
  blind.truth.reset();
  EXPECT_FALSE(loc.locate(blind));
  EXPECT_FALSE(loc.locate(blind));
  EXPECT_EQ(loc.status().state, tracking::TrackingState::Lost);
  EXPECT_EQ(loc.status().lost_count, 1u);
  EXPECT_TRUE(loc.locate(frame_at(rig_at(0, 0), 3)));  // back
  EXPECT_EQ(loc.status().to_json()["state"], "tracking");
}

TEST(RigLocaliser, OffIsAStaticRigAtTheFirstPose) {
  TrackingConfig t;
  t.method = "off";
  RigLocaliser loc(t, WorldConfig{}, calibration(), nullptr);
  expect_same(*loc.locate(frame_at(rig_at(0.3, 20), 0)), rig_at(0.3, 20));
  expect_same(*loc.locate(frame_at(rig_at(0.9, 50), 1)), rig_at(0.3, 20));
  EXPECT_EQ(loc.status().to_json()["state"], "off");
}

TEST(RigLocaliser, DenseTracksFromTheFirstFramesRigPose) {
  // The tracker's world is its first camera; the rig anchor puts that camera where the
  // source's first pose says. (With the scaffold tracker every pose is the first one.)
  RigLocaliser loc(TrackingConfig{}, WorldConfig{}, calibration(), nullptr);
  const auto p = loc.locate(frame_at(rig_at(0.3, 20), 0));
  ASSERT_TRUE(p);
  expect_same(*p, rig_at(0.3, 20));
  EXPECT_EQ(loc.status().method, "dense");
}

TEST(RigLocaliser, FloorWaitsForAPlaneAndThenKeepsIt) {
  TrackingConfig t;
  t.method = "truth";
  WorldConfig w;
  w.anchor = "floor";
  RigLocaliser loc(t, w, calibration(), nullptr);
  EXPECT_FALSE(loc.locate(frame_at(rig_at(0, 0), 0))) << "no depth: no floor, no objects";
  EXPECT_FALSE(loc.status().anchor_found);
  EXPECT_EQ(loc.status().to_json()["pose"], nullptr);
}

TEST(RigLocaliser, UnknownNamesThrow) {
  TrackingConfig t;
  t.method = "icp";
  EXPECT_THROW(RigLocaliser(t, WorldConfig{}, calibration(), nullptr), std::invalid_argument);
  WorldConfig w;
  w.anchor = "table";
  EXPECT_THROW(RigLocaliser(TrackingConfig{}, w, calibration(), nullptr), std::invalid_argument);
  w.anchor = "marker";
  w.marker = "chessboard:9x6:25";
  EXPECT_THROW(RigLocaliser(TrackingConfig{}, w, calibration(), nullptr), std::invalid_argument);
}

TEST(WorldStep, CountsTheOriginsShiftAndTheRotationsArc) {
  Pose a, b;
  b.translation = Eigen::Vector3d(0.003, 0, 0);
  EXPECT_NEAR(world_step_m(a, b), 0.003, 1e-12);
  Pose c;
  c.rotation = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(world_step_m(a, c, 0.25), 0.0025, 1e-9);
}

}  // namespace
}  // namespace probeless::world
