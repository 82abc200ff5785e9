#include "drivers/sim/sim_world.hpp"

#include <cmath>
#include <numbers>

#include "drivers/sim/sim_calibration_views.hpp"
#include "drivers/sim/sim_random.hpp"
#include "drivers/sim/sim_scene.hpp"

namespace probeless::sim {

namespace {

// The room and what stands in it (metres, world z up). docs/sim.md has a plan view.
constexpr double kTableTop = 0.75;
const Eigen::Vector3d kAnchor{0.0, 0.6, kTableTop};
constexpr double kRigHeight = 1.15;  // colour camera centre above the floor
// Rig to anchor, horizontally: the back wall is then 3.6 m away, inside the depth range.
constexpr double kOrbitRadius = 1.7;
constexpr double kOrbitPeriod = 60.0;  // seconds per revolution ("slow orbit")
// Scripted events: lamp B is on for the first half of every period.
constexpr double kLampPeriod = 12.0;
// The arm reaches in every kArmPeriod seconds and is in view for about half of it.
constexpr double kArmPeriod = 5.0;
// The tabletop view: a person standing at the table, the rig 0.7 m above the top and 0.9 m
// from the anchor, pitched down onto it (38 degrees), swinging +-20 degrees around it every
// 20 s: the board fills a third of the picture at ~1.1 m.
constexpr double kTabletopHeight = 1.45, kTabletopRadius = 0.9;
constexpr double kTabletopSwingDeg = 20.0, kTabletopPeriod = 20.0;
// The near hand (near_occluder=1): over the middle of the view at t = 1.5 s + k 6 s, in view
// from about t = 0.2 to 2.8 s of every period (the arm: 2 to 4.5 s of every 5).
constexpr double kNearHandPeriod = 6.0;

}  // namespace

SimWorld::SimWorld(std::uint64_t seed, bool board) : seed_(seed), board_(board) {
  for (int i = 0; i < static_cast<int>(shake_phase_.size()); ++i)
    shake_phase_[i] = 2.0 * std::numbers::pi * uniform01(hash_combine(seed, 900 + i));
  WorldBuilder builder(seed, patches_);
  build_geometry(builder);
  bake_lighting(builder);
  render_light_probes();
}

int SimWorld::lamp_state(double t) {
  const double phase = std::fmod(t, kLampPeriod);
  return (phase >= 0 && phase < 0.5 * kLampPeriod) ? 1 : 0;
}

Pose SimWorld::rig_pose(TrajectoryKind kind, double t) const {
  if (kind == TrajectoryKind::Calibration) return calibration_rig_pose(t);
  double theta = 0;
  if (kind == TrajectoryKind::Orbit) theta = 2 * std::numbers::pi * t / kOrbitPeriod;
  if (kind == TrajectoryKind::Tabletop) {
    theta = kTabletopSwingDeg * std::numbers::pi / 180 *
            std::sin(2 * std::numbers::pi * t / kTabletopPeriod);
    const Eigen::Vector3d forward(std::sin(theta), std::cos(theta), 0.0);
    const Eigen::Vector3d right(std::cos(theta), -std::sin(theta), 0.0);
    Eigen::Matrix3d r;
    r << right, forward, Eigen::Vector3d::UnitZ();
    const double pitch = std::atan2(kTabletopHeight - kAnchor.z(), kTabletopRadius);
    Pose pose;
    pose.translation =
        Eigen::Vector3d(kAnchor.x(), kAnchor.y(), kTabletopHeight) - kTabletopRadius * forward;
    pose.rotation = Eigen::Quaterniond(r) * Eigen::AngleAxisd(-pitch, Eigen::Vector3d::UnitX());
    return pose;
  }
  const Eigen::Vector3d forward(std::sin(theta), std::cos(theta), 0.0);
  const Eigen::Vector3d right(std::cos(theta), -std::sin(theta), 0.0);
  Pose pose;
  pose.translation = Eigen::Vector3d(kAnchor.x(), kAnchor.y(), kRigHeight) - kOrbitRadius * forward;
  Eigen::Matrix3d r;
  r << right, forward, Eigen::Vector3d::UnitZ();
  pose.rotation = Eigen::Quaterniond(r);
  if (kind == TrajectoryKind::Handheld) {
    // A hand holding the rig: slow sway, arm tremor at a few hertz, and a faint fast jitter
    // (sums of sines with seeded phases: smooth, deterministic, any t).
    const auto& ph = shake_phase_;
    const auto wave = [&](double amp, double hz, int k) {
      return amp * std::sin(2 * std::numbers::pi * hz * t + ph[k]);
    };
    const Eigen::Vector3d shift(wave(0.008, 0.23, 0) + wave(0.003, 1.3, 1) + wave(0.0006, 8.7, 2),
                                wave(0.006, 0.17, 3) + wave(0.002, 1.1, 4),
                                wave(0.005, 0.31, 5) + wave(0.002, 1.7, 6) + wave(0.0005, 7.9, 7));
    const Eigen::Vector3d angles(wave(0.008, 0.9, 8) + wave(0.0015, 5.3, 9), wave(0.006, 0.7, 10),
                                 wave(0.009, 1.2, 11) + wave(0.001, 6.1, 0));
    const Eigen::Quaterniond shake = Eigen::AngleAxisd(angles.z(), Eigen::Vector3d::UnitZ()) *
                                     Eigen::AngleAxisd(angles.x(), Eigen::Vector3d::UnitX()) *
                                     Eigen::AngleAxisd(angles.y(), Eigen::Vector3d::UnitY());
    pose.translation += pose.rotation * shift;
    pose.rotation = (pose.rotation * shake).normalized();
  }
  return pose;
}

// The arm sweeps in from the right of the camera, across the line of sight to the object,
// and back out: in view for about half of every kArmPeriod seconds. A rigid chain (hand,
// forearm, upper arm) so its size never changes; placed in the frame of the current view.
Occluder SimWorld::occluder(double t, const Eigen::Vector3d& camera_centre) const {
  const Eigen::Vector3d target = light_probe_position();
  const Eigen::Vector3d to_camera = camera_centre - target;
  Eigen::Vector3d back(to_camera.x(), to_camera.y(), 0.0);
  if (back.norm() < 1e-6) back = Eigen::Vector3d::UnitY();
  back.normalize();
  const Eigen::Vector3d right =
      Eigen::Vector3d::UnitZ().cross(back);  // right, seen from the camera
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d middle = target + 0.45 * to_camera;

  const double phase = std::fmod(t / kArmPeriod + 0.6, 1.0);
  double lateral = 0.9;  // at rest: out of view
  if (phase < 0.5) {
    const double s = std::sin(std::numbers::pi * phase / 0.5);
    lateral = 0.9 - 1.15 * s * s;
  }
  const Eigen::Vector3d hand =
      middle + lateral * right + 0.02 * std::sin(2 * std::numbers::pi * t / 1.7) * up;
  const Eigen::Vector3d fingers = hand - 0.09 * right;
  const Eigen::Vector3d elbow = hand + 0.27 * right + 0.04 * back - 0.05 * up;
  const Eigen::Vector3d shoulder = elbow + 0.25 * right + 0.05 * back + 0.18 * up;
  Occluder o;
  o.capsules = {{fingers.cast<float>(), hand.cast<float>(), 0.04f},
                {hand.cast<float>(), elbow.cast<float>(), 0.045f},
                {elbow.cast<float>(), shoulder.cast<float>(), 0.055f}};
  return o;
}

std::vector<Capsule> SimWorld::near_hand(double t, const Pose& T_world_camera) {
  // Camera frame (x right, y down, z forward), metres. At 0.3 m a 4.5 cm palm is ~80 px
  // across: a hand held up in front of the camera, nearer than the sensor can measure.
  const double phase = std::fmod(t / kNearHandPeriod, 1.0);
  double x = 0.40;  // at rest: out of view to the right
  if (phase < 0.5) {
    const double s = std::sin(std::numbers::pi * phase / 0.5);
    x = 0.40 - 0.43 * s * s;
  }
  const double y = 0.03 + 0.01 * std::sin(2 * std::numbers::pi * t / 1.3);
  const Eigen::Vector3d palm(x, y, 0.30), fingers(x - 0.02, y - 0.08, 0.31);
  const Eigen::Vector3d wrist(x + 0.03, y + 0.07, 0.31), elbow(x + 0.20, y + 0.30, 0.45);
  const auto world = [&](const Eigen::Vector3d& p) -> Eigen::Vector3f {
    const Eigen::Vector3d q = T_world_camera * p;
    return q.cast<float>();
  };
  return {{world(fingers), world(palm), 0.035f},
          {world(palm), world(wrist), 0.045f},
          {world(wrist), world(elbow), 0.04f}};
}

Eigen::Vector3d object_anchor() {
  return kAnchor;
}
double table_top_height_m() {
  return kTableTop;
}
const char* board_spec() {
  return "charuco:5x4:80:60:4x4_50";  // sim_board.cpp draws it
}
Pose board_world_pose() {
  Pose p;
  p.translation = kAnchor + Eigen::Vector3d(0, 0, 0.001);  // on the 1 mm card
  return p;
}
double fisheye_radiance_per_converted() {
  return 3839.0 / 600.0;
}

Eigen::Vector3d light_probe_position() {
  return kAnchor + Eigen::Vector3d(0, 0, 0.1);
}

}  // namespace probeless::sim
