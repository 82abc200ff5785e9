#include <gtest/gtest.h>

#include <numbers>

#include "core/pose.hpp"

namespace probeless {
namespace {

Pose make_pose(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& t) {
  Pose p;
  p.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
  p.translation = t;
  return p;
}

TEST(Pose, InverseComposesToIdentity) {
  const Pose p = make_pose(0.7, {1, 2, 3}, {0.5, -1, 2});
  const Pose id = p * p.inverse();
  EXPECT_NEAR(id.translation.norm(), 0.0, 1e-12);
  EXPECT_NEAR(id.rotation.angularDistance(Eigen::Quaterniond::Identity()), 0.0, 1e-12);
  const Eigen::Vector3d x{0.3, 0.2, -0.1};
  EXPECT_LT((p.inverse() * (p * x) - x).norm(), 1e-12);
}

TEST(Pose, MatrixRoundTrip) {
  const Pose p = make_pose(-1.1, {0, 1, 1}, {3, 2, 1});
  const Pose q = Pose::from_matrix(p.matrix());
  EXPECT_LT((q.translation - p.translation).norm(), 1e-12);
  EXPECT_LT(q.rotation.angularDistance(p.rotation), 1e-12);
}

// Closed form: interpolating a rotation about a fixed axis by angle a at t gives t * a about
// the same axis; translation moves on the straight line.
TEST(Pose, InterpolationAboutFixedAxisIsLinearInAngle) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, -1, 0.5).normalized();
  const Pose a = make_pose(0.2, axis, {0, 0, 0});
  const Pose b = make_pose(1.4, axis, {2, -4, 6});
  for (double t : {0.0, 0.25, 0.5, 0.9, 1.0}) {
    const Pose p = interpolate(a, b, t);
    const Pose expected = make_pose(0.2 + t * 1.2, axis, t * Eigen::Vector3d(2, -4, 6));
    EXPECT_NEAR(p.rotation.angularDistance(expected.rotation), 0.0, 1e-12) << "t=" << t;
    EXPECT_LT((p.translation - expected.translation).norm(), 1e-12) << "t=" << t;
  }
}

TEST(Pose, InterpolationTakesTheShortArc) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Pose a = make_pose(std::numbers::pi - 0.1, z, {0, 0, 0});
  const Pose b = make_pose(-std::numbers::pi + 0.1, z, {0, 0, 0});  // 0.2 rad away via pi
  const Pose mid = interpolate(a, b, 0.5);
  EXPECT_NEAR(mid.rotation.angularDistance(make_pose(std::numbers::pi, z, Eigen::Vector3d::Zero()).rotation),
              0.0, 1e-9);
}

TEST(Trajectory, InterpolatesBetweenSamplesAndRefusesOutside) {
  Trajectory traj;
  traj.append(1000, make_pose(0.0, {0, 0, 1}, {0, 0, 0}));
  traj.append(3000, make_pose(1.0, {0, 0, 1}, {2, 0, 0}));
  EXPECT_FALSE(traj.at(999).has_value());
  EXPECT_FALSE(traj.at(3001).has_value());
  const auto mid = traj.at(2000);
  ASSERT_TRUE(mid.has_value());
  EXPECT_NEAR(mid->translation.x(), 1.0, 1e-12);
  EXPECT_NEAR(mid->rotation.angularDistance(make_pose(0.5, {0, 0, 1}, Eigen::Vector3d::Zero()).rotation),
              0, 1e-12);
  EXPECT_THROW(traj.append(3000, Pose{}), std::invalid_argument);
}

}  // namespace
}  // namespace probeless
