#pragma once
// The synthetic rig's world: an analytic room (axis-aligned boxes, a mirror ball, area lights,
// a window) with its lighting baked per lamp state, the scripted events, the rig
// trajectories and the moving occluder. Immutable after construction and shared by both
// sources: everything a frame shows is a function of (seed, time).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/cubemap.hpp"
#include "core/pose.hpp"
#include "drivers/sim/sim_rig.hpp"

namespace probeless::sim {

// A lit rectangle origin + a u + b v (a in [0, size_u], b in [0, size_v]) with its outgoing
// radiance baked into texels of edge `texel` metres, one table per lamp state.
struct Patch {
  Eigen::Vector3f origin, u, v, normal;
  float size_u = 0, size_v = 0, texel = 0;
  int nu = 0, nv = 0;
  // Lookups: u and v are world axes, so texel coordinates are one multiply-add per axis,
  // fu = p[axis_u] * scale_u + offset_u (texel centres at integers), clamped to max_fu.
  int axis_u = 0, axis_v = 1;
  float scale_u = 0, offset_u = 0, scale_v = 0, offset_v = 0, max_fu = 0, max_fv = 0;
  bool no_depth = false;  // structured light fails on it (very dark)
  // World-space boxes (lo, hi) on the patch without depth: glass, a doorway into the dark.
  std::vector<std::array<Eigen::Vector3f, 2>> no_depth_boxes;
  // [lamp state][j * nu + i], RGB and a pad (one aligned 4-wide load per texel).
  std::vector<std::vector<Eigen::Array4f>> radiance;
};

// Axis-aligned box; patch[axis * 2 + side] is its face on the low (0) or high (1) side, -1 when
// the face can never be seen.
struct Box {
  Eigen::Vector3f lo, hi;
  std::array<int, 6> patch{-1, -1, -1, -1, -1, -1};
};

struct Sphere {  // a mirror ball: reflects the scene, gives no depth
  Eigen::Vector3f centre;
  float radius = 0;
  Eigen::Vector3f reflectance;
};

struct Capsule {
  Eigen::Vector3f a, b;
  float radius = 0;
};

// A real box that moves (the moving-object scenes, sim_moving_scene.hpp): Lambertian with a
// flat albedo, lit like the arm (ambient, the lights as points, no shadows either way).
struct MovingBox {
  Eigen::Vector3f lo, hi, albedo;
};

// A primitive reference in a candidate list (a tile's, or all static ones). OccluderBox
// indexes Occluder::boxes.
struct PrimRef {
  enum class Kind : std::uint8_t { Box, Sphere, Capsule, OccluderBox } kind;
  std::uint8_t index;
};

// The moving occluders: the arm (hand, forearm, upper arm), and with `near_occluder=1` a
// hand close in front of the colour camera (hand, forearm) after them; with `scene=NAME` that
// scene's objects instead of the arm. A hit on boxes[j] is Hit::Kind::Occluder with index
// capsules.size() + j, so every reader of the occluder flag sees a moving box as moving.
struct Occluder {
  std::vector<Capsule> capsules;
  std::vector<MovingBox> boxes;
};

// A rectangular emitter: centre +- u_half +- v_half, emitting towards `normal`; `radiance` is
// its mean (the lighting bake samples the emission of the patch it lies on instead).
struct AreaLight {
  Eigen::Vector3f centre, u_half, v_half, normal, radiance;
  int switch_bit = -1;  // -1: always on; else on when this bit of the lamp state is set
  int patch = -1;       // the patch it is part of (ceiling, back wall)
};

class WorldBuilder;

class SimWorld {
 public:
  static constexpr int kLampStates = 2;  // one scripted lamp: bit 0 = on

  // `board`: the ChArUco card on the table (sim_board.hpp).
  explicit SimWorld(std::uint64_t seed, bool board = false);

  std::uint64_t seed() const { return seed_; }

  // Scripted events: which lamps are on at time t (seconds since the start).
  static int lamp_state(double t);
  // T_world_rig at time t. Rig frame: x right, y forward, z up.
  Pose rig_pose(TrajectoryKind kind, double t) const;
  // The arm at time t, placed relative to where the colour camera is.
  Occluder occluder(double t, const Eigen::Vector3d& camera_centre) const;
  // The near hand at time t (SimOptions::near_occluder): a hand and forearm 0.25-0.45 m in
  // front of the colour camera, closer than the depth sensor's 0.5 m minimum range, sweeping
  // in from the right across the middle of the view every kNearHandPeriod seconds.
  static std::vector<Capsule> near_hand(double t, const Pose& T_world_camera);
  // Radiance seen from light_probe_position(), computed once per lamp state.
  const std::shared_ptr<const Cubemap>& light(int lamp_state) const { return light_[lamp_state]; }

  const Eigen::Vector3f& room_lo() const { return room_lo_; }
  const Eigen::Vector3f& room_hi() const { return room_hi_; }
  const std::array<int, 6>& room_patches() const { return room_patch_; }
  const std::vector<Patch>& patches() const { return patches_; }
  const std::vector<Box>& boxes() const { return boxes_; }
  const std::vector<Sphere>& spheres() const { return spheres_; }
  const std::vector<AreaLight>& lights() const { return lights_; }
  const std::vector<PrimRef>& static_prims() const { return static_prims_; }
  // Radiance leaving the occluder's skin per unit albedo and unit cosine, per lamp state:
  // the ambient part and the lights as distant points (no shadows on the arm).
  const Eigen::Vector3f& skin_albedo() const { return skin_albedo_; }
  const Eigen::Vector3f& ambient(int lamp_state) const { return ambient_[lamp_state]; }

 private:
  void build_geometry(WorldBuilder& builder);
  void bake_lighting(const WorldBuilder& builder);
  void render_light_probes();

  std::uint64_t seed_;
  bool board_ = false;
  Eigen::Vector3f room_lo_, room_hi_;
  std::array<int, 6> room_patch_{};
  std::vector<Patch> patches_;
  std::vector<Box> boxes_;
  std::vector<Sphere> spheres_;
  std::vector<AreaLight> lights_;
  std::vector<PrimRef> static_prims_;
  Eigen::Vector3f skin_albedo_;
  std::array<Eigen::Vector3f, kLampStates> ambient_;
  std::array<std::shared_ptr<const Cubemap>, kLampStates> light_;
  std::array<double, 12> shake_phase_{};
};

}  // namespace probeless::sim
