#include "drivers/sim/sim_moving_scene.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace probeless::sim {

namespace {

using Vec3 = Eigen::Vector3d;

// Every scene changes at kEventS, 2 s in: the light stage has published snapshots for a
// second by then (its first keyframe and colour exposure), so the state before the change is
// settled. A motion takes kMotionS. The run ends at kDurationS, before lamp B switches off
// at 6 s.
constexpr double kEventS = 2.0, kMotionS = 0.5, kDurationS = 5.5;
// The hand holds still next to the sphere for 1.5 s, then withdraws.
constexpr double kHandWithdrawS = 3.5;

// The box: 12 x 12 cm, 16 cm tall (its top 6 cm above the sphere's centre, so it crosses the
// centre's horizon as a real object beside a small virtual one does), saturated blue, unlike
// the table's wood and the sage wall behind it, so a reflection without it differs plainly.
constexpr double kBoxHalf = 0.06, kBoxHeight = 0.16;
const Eigen::Vector3f kBoxAlbedo(0.12f, 0.28f, 0.75f);
// Where it rests: right of the sphere, 18 cm from its centre to the box's near face and 4 cm
// nearer the static rig, so the sphere, seen from the rig's side, shows it well inside its
// rim (behind the sphere it is squeezed into the rim, where a pixel's reflected direction
// sweeps many texels). box_slides starts it at the table's front right corner.
const Vec3 kBoxRest(0.24, 0.56, 0), kBoxStart(0.62, 0.30, 0);

// The hand (fingers r 3 cm, palm 4.5 cm, forearm 4 cm, skin as the arm's) comes in along
// kHandDir from the left, in front and above, its palm and fingers across that direction (a
// hand about to take the sphere from the side), and stops with the middle of the palm 19 cm
// from the sphere's centre: 4.5 cm from the surface of the 10 cm sphere at
// light_probe_position(). Across, it spans ~45 degrees of the sphere's view; end on, a third.
const Vec3 kHandDir = Vec3(0.85, 0.25, -0.2).normalized();
const Vec3 kHandAcross = Vec3::UnitZ().cross(kHandDir).normalized();
constexpr double kHandRestDistance = 0.19;
constexpr double kHandTravel = 0.7;  // metres along kHandDir

double smoothstep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3 - 2 * u);
}

MovingBox box_at(const Vec3& centre_xy) {
  const auto top = static_cast<float>(table_top_height_m());
  const Eigen::Vector3f c = centre_xy.cast<float>();
  const auto h = static_cast<float>(kBoxHalf);
  return {{c.x() - h, c.y() - h, top},
          {c.x() + h, c.y() + h, top + static_cast<float>(kBoxHeight)},
          kBoxAlbedo};
}

std::vector<Capsule> hand_at(double reach) {  // reach: 0 at the start, 1 at rest
  const Vec3 middle =
      light_probe_position() - (kHandRestDistance + (1 - reach) * kHandTravel) * kHandDir;
  const Vec3 wrist = middle - 0.08 * kHandAcross, knuckles = middle + 0.02 * kHandAcross;
  const Vec3 tips = middle + 0.09 * kHandAcross;
  const Vec3 elbow = wrist - 0.28 * kHandDir + Vec3(0, 0, 0.06);
  const auto f = [](const Vec3& p) -> Eigen::Vector3f { return p.cast<float>(); };
  return {
      {f(tips), f(knuckles), 0.03f}, {f(knuckles), f(wrist), 0.045f}, {f(wrist), f(elbow), 0.04f}};
}

constexpr std::array<SceneEvent, 1> kSlideEvents{
    {{SceneEvent::Kind::Arrival, kEventS, kEventS - kMotionS}}};
constexpr std::array<SceneEvent, 2> kHandEvents{
    {{SceneEvent::Kind::Arrival, kEventS, kEventS - kMotionS},
     {SceneEvent::Kind::Removal, kHandWithdrawS + kMotionS, kHandWithdrawS}}};
constexpr std::array<SceneEvent, 1> kRemovedEvents{
    {{SceneEvent::Kind::Removal, kEventS, kEventS - kMotionS}}};
constexpr std::array<SceneEvent, 1> kAppearsEvents{
    {{SceneEvent::Kind::Arrival, kEventS, kEventS - kMotionS}}};

const std::array<MovingSceneSpec, 4> kScenes{{
    {MovingScene::BoxSlides, "box_slides",
     "a box slides across the table from its front right corner to rest beside the sphere "
     "(1.5-2.0 s)",
     kDurationS, kSlideEvents},
    {MovingScene::HandApproaches, "hand_approaches",
     "a hand reaches in to 4.5 cm from the sphere (1.5-2.0 s), holds, and withdraws "
     "(3.5-4.0 s)",
     kDurationS, kHandEvents},
    {MovingScene::BoxRemoved, "box_removed", "the box beside the sphere vanishes at 2.0 s",
     kDurationS, kRemovedEvents},
    {MovingScene::BoxAppears, "box_appears", "the box appears beside the sphere at 2.0 s",
     kDurationS, kAppearsEvents},
}};

}  // namespace

std::span<const MovingSceneSpec> moving_scenes() {
  return kScenes;
}

const MovingSceneSpec& moving_scene_spec(MovingScene scene) {
  for (const auto& s : kScenes)
    if (s.id == scene) return s;
  throw std::invalid_argument("moving_scene_spec: no scene");
}

std::optional<MovingScene> find_moving_scene(std::string_view name) {
  for (const auto& s : kScenes)
    if (s.name == name) return s.id;
  return std::nullopt;
}

std::string moving_scene_names(std::string_view separator) {
  std::string out;
  for (const auto& s : kScenes) {
    if (!out.empty()) out += separator;
    out += s.name;
  }
  return out;
}

Occluder moving_scene_objects(MovingScene scene, double t) {
  Occluder o;
  switch (scene) {
    case MovingScene::None:
      break;
    case MovingScene::BoxSlides:
      o.boxes.push_back(box_at(kBoxStart + smoothstep((t - (kEventS - kMotionS)) / kMotionS) *
                                               (kBoxRest - kBoxStart)));
      break;
    case MovingScene::HandApproaches: {
      const double reach = t < kHandWithdrawS ? smoothstep((t - (kEventS - kMotionS)) / kMotionS)
                                              : 1 - smoothstep((t - kHandWithdrawS) / kMotionS);
      o.capsules = hand_at(reach);
      break;
    }
    case MovingScene::BoxRemoved:
      if (t < kEventS) o.boxes.push_back(box_at(kBoxRest));
      break;
    case MovingScene::BoxAppears:
      if (t >= kEventS) o.boxes.push_back(box_at(kBoxRest));
      break;
  }
  return o;
}

}  // namespace probeless::sim
