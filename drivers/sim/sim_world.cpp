#include "drivers/sim/sim_world.hpp"

#include <cmath>
#include <functional>
#include <numbers>

#include "drivers/sim/sim_random.hpp"
#include "drivers/sim/sim_trace.hpp"
#include "drivers/sim/worker_pool.hpp"

namespace probeless::sim {

namespace {

using Vec3 = Eigen::Vector3f;
constexpr float kPi = std::numbers::pi_v<float>;

// The room and what stands in it (metres, world z up). docs/sim.md has a plan view.
const Vec3 kRoomLo{-2.5f, -2.5f, 0.0f};
const Vec3 kRoomHi{2.5f, 2.5f, 2.7f};
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

// Window in the back wall (y = 2.5) and the two ceiling lamps.
constexpr float kWinX0 = 0.7f, kWinX1 = 1.8f, kWinZ0 = 0.9f, kWinZ1 = 2.2f;
// A doorway in the right wall onto an unlit corridor: the darkest place in view, and beyond
// the depth sensor's range.
constexpr float kDoorY0 = -1.9f, kDoorY1 = -1.0f, kDoorZ1 = 2.05f;
constexpr float kMullion = 0.035f;

// Value noise on an integer lattice, smoothly interpolated, in [0, 1).
float lattice(std::int64_t x, std::int64_t y, std::uint64_t seed) {
  return uniform01(hash_combine(
      seed, static_cast<std::uint64_t>(x) * 0x9E3779B1u ^ (static_cast<std::uint64_t>(y) << 32)));
}

float value_noise(float x, float y, std::uint64_t seed) {
  const float fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  float tx = x - fx, ty = y - fy;
  tx = tx * tx * (3 - 2 * tx);
  ty = ty * ty * (3 - 2 * ty);
  const float a = lattice(ix, iy, seed), b = lattice(ix + 1, iy, seed);
  const float c = lattice(ix, iy + 1, seed), d = lattice(ix + 1, iy + 1, seed);
  return (a + tx * (b - a)) + ty * ((c + tx * (d - c)) - (a + tx * (b - a)));
}

// Fractal sum of value noise, in [0, 1).
float fbm(float x, float y, std::uint64_t seed, int octaves = 4) {
  float sum = 0, amp = 0.5f, norm = 0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * value_noise(x, y, seed + o);
    norm += amp;
    x *= 2.03f;
    y *= 2.03f;
    amp *= 0.5f;
  }
  return sum / norm;
}

float smooth_band(float x, float edge0, float edge1) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

}  // namespace

using AlbedoFn = std::function<Vec3(const Vec3&)>;
using EmissionFn = std::function<Vec3(const Vec3&, int lamp_state)>;

// How a patch looks, used while baking and then dropped.
struct PatchSpec {
  AlbedoFn albedo;
  EmissionFn emission;  // may be empty
  float light_spacing;  // lighting is baked on a grid this coarse, then interpolated
};

class WorldBuilder {
 public:
  WorldBuilder(std::uint64_t seed, std::vector<Patch>& patches) : seed_(seed), patches_(patches) {}

  // A face of the axis-aligned box [lo, hi] on `side` (0 low, 1 high) of `axis`, facing out of
  // the box (or into it, for the room).
  int add_face(const Vec3& lo, const Vec3& hi, int axis, int side, bool inward, float texel,
               float light_spacing, AlbedoFn albedo, EmissionFn emission = {}) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const bool positive = (side == 1) != inward;
    Patch p;
    p.normal = Vec3::Unit(axis) * (positive ? 1.0f : -1.0f);
    const int au = positive ? a1 : a2, av = positive ? a2 : a1;
    p.u = Vec3::Unit(au);
    p.v = Vec3::Unit(av);
    p.origin = lo;
    p.origin[axis] = side ? hi[axis] : lo[axis];
    p.size_u = hi[au] - lo[au];
    p.size_v = hi[av] - lo[av];
    p.texel = texel;
    p.nu = std::max(2, static_cast<int>(std::ceil(p.size_u / texel)));
    p.nv = std::max(2, static_cast<int>(std::ceil(p.size_v / texel)));
    p.axis_u = au;
    p.axis_v = av;
    p.scale_u = p.u[au] / texel;
    p.scale_v = p.v[av] / texel;
    p.offset_u = -p.origin[au] * p.scale_u - 0.5f;
    p.offset_v = -p.origin[av] * p.scale_v - 0.5f;
    p.max_fu = static_cast<float>(p.nu) - 1.001f;
    p.max_fv = static_cast<float>(p.nv) - 1.001f;
    patches_.push_back(std::move(p));
    specs_.push_back({std::move(albedo), std::move(emission), light_spacing});
    return static_cast<int>(patches_.size()) - 1;
  }

  // A box with the faces in `faces` (bit axis * 2 + side) visible.
  Box add_box(const Vec3& lo, const Vec3& hi, unsigned faces, float texel, float light_spacing,
              const AlbedoFn& albedo) {
    Box b{lo, hi, {}};
    for (int f = 0; f < 6; ++f)
      b.patch[f] = (faces >> f) & 1u
                       ? add_face(lo, hi, f / 2, f % 2, false, texel, light_spacing, albedo)
                       : -1;
    return b;
  }

  const std::vector<PatchSpec>& specs() const { return specs_; }
  std::uint64_t seed() const { return seed_; }

 private:
  std::uint64_t seed_;
  std::vector<Patch>& patches_;
  std::vector<PatchSpec> specs_;
};

namespace {

constexpr unsigned kAllFaces = 0x3f;
constexpr unsigned face_bit(int axis, int side) {
  return 1u << (axis * 2 + side);
}

// The lamps and the window as light sources, and their appearance on the ceiling and wall.
struct Emitters {
  AreaLight lamp_a, lamp_b, window;
};

Emitters make_emitters() {
  Emitters e;
  e.lamp_a = {{-0.6f, 0.3f, 2.7f},
              {0.3f, 0, 0},
              {0, 0.3f, 0},
              {0, 0, -1},
              Vec3(1.0f, 0.86f, 0.70f) * 10000.0f,
              -1,
              false};
  e.lamp_b = {{1.3f, -1.2f, 2.7f},
              {0.3f, 0, 0},
              {0, 0.3f, 0},
              {0, 0, -1},
              Vec3(0.92f, 0.96f, 1.0f) * 10000.0f,
              0,
              false};
  const float wx = 0.5f * (kWinX1 - kWinX0), wz = 0.5f * (kWinZ1 - kWinZ0);
  e.window = {{0.5f * (kWinX0 + kWinX1), 2.5f, 0.5f * (kWinZ0 + kWinZ1)},
              {wx, 0, 0},
              {0, 0, wz},
              {0, -1, 0},
              Vec3::Zero(),
              -1,
              true};
  return e;
}

// Daylight through the window: sky above a horizon of trees; the mullions are wall.
bool in_window_glass(const Vec3& p) {
  if (p.x() < kWinX0 + kMullion || p.x() > kWinX1 - kMullion || p.z() < kWinZ0 + kMullion ||
      p.z() > kWinZ1 - kMullion)
    return false;
  const float mx = 0.5f * (kWinX0 + kWinX1), mz = 0.5f * (kWinZ0 + kWinZ1) + 0.15f;
  return std::abs(p.x() - mx) > 0.5f * kMullion && std::abs(p.z() - mz) > 0.5f * kMullion;
}

Vec3 sky_radiance(const Vec3& p, std::uint64_t seed) {
  const float horizon = 1.25f + 0.12f * fbm(p.x() * 3.0f, 0.0f, seed + 700, 3);
  if (p.z() < horizon) {
    const float leaf = fbm(p.x() * 25.0f, p.z() * 25.0f, seed + 710, 3);
    return Vec3(0.30f, 0.42f, 0.22f) * (1500.0f + 2500.0f * leaf);
  }
  const float up = std::clamp((p.z() - horizon) / (kWinZ1 - horizon), 0.0f, 1.0f);
  const float cloud = smooth_band(fbm(p.x() * 4.0f, p.z() * 6.0f, seed + 720, 4), 0.45f, 0.7f);
  const Vec3 blue = Vec3(0.62f, 0.78f, 1.0f) * (1.0e4f + 6.0e3f * up);
  const Vec3 white = Vec3(1.0f, 1.0f, 0.98f) * 2.5e4f;
  return blue + cloud * (white - blue);
}

bool in_lamp(const AreaLight& l, const Vec3& p) {
  return std::abs(p.x() - l.centre.x()) <= l.u_half.norm() &&
         std::abs(p.y() - l.centre.y()) <= l.v_half.norm();
}

}  // namespace

SimWorld::SimWorld(std::uint64_t seed) : seed_(seed) {
  for (int i = 0; i < static_cast<int>(shake_phase_.size()); ++i)
    shake_phase_[i] = 2.0 * std::numbers::pi * uniform01(hash_combine(seed, 900 + i));
  WorldBuilder builder(seed, patches_);
  build_geometry(builder);
  bake_lighting(builder);
  render_light_probes();
}

void SimWorld::build_geometry(WorldBuilder& b) {
  room_lo_ = kRoomLo;
  room_hi_ = kRoomHi;
  skin_albedo_ = Vec3(0.62f, 0.43f, 0.34f);
  const std::uint64_t s = seed_;
  const Emitters em = make_emitters();

  // Floor: oak planks, and a patterned rug under the table.
  const AlbedoFn floor = [s](const Vec3& p) -> Vec3 {
    const float rx0 = -1.3f, rx1 = 1.3f, ry0 = -0.5f, ry1 = 1.7f;
    if (p.x() > rx0 && p.x() < rx1 && p.y() > ry0 && p.y() < ry1) {
      const float border = std::min({p.x() - rx0, rx1 - p.x(), p.y() - ry0, ry1 - p.y()});
      const float weave = 0.85f + 0.3f * value_noise(p.x() * 300.0f, p.y() * 300.0f, s + 11);
      if (border < 0.12f) return Vec3(0.78f, 0.70f, 0.52f) * weave;
      const float u = std::abs(std::fmod(p.x() + 10.0f, 0.4f) - 0.2f);
      const float v = std::abs(std::fmod(p.y() + 10.0f, 0.4f) - 0.2f);
      const bool diamond = u + v < 0.12f;
      return (diamond ? Vec3(0.80f, 0.72f, 0.50f) : Vec3(0.45f, 0.09f, 0.08f)) * weave;
    }
    const float plank_w = 0.14f;
    const auto row = static_cast<std::int64_t>(std::floor((p.y() + 2.5f) / plank_w));
    const float offset = 1.2f * lattice(row, 7, s + 20);
    const auto col = static_cast<std::int64_t>(std::floor((p.x() + 2.5f + offset) / 1.2f));
    const float tint = 0.75f + 0.5f * lattice(row, col, s + 21);
    const float grain = 0.8f + 0.4f * fbm(p.x() * 3.0f, p.y() * 60.0f, s + 22, 3);
    const float in_row = std::fmod(p.y() + 2.5f, plank_w);
    const float in_col = std::fmod(p.x() + 2.5f + offset, 1.2f);
    const float gap = (in_row < 0.003f || in_col < 0.003f) ? 0.35f : 1.0f;
    return Vec3(0.46f, 0.31f, 0.18f) * (tint * grain * gap);
  };
  const AlbedoFn plaster = [s](const Vec3& p) -> Vec3 {
    const float m = 0.92f + 0.12f * fbm(p.x() * 2.0f + p.y() * 2.0f, p.z() * 2.0f, s + 30, 3) +
                    0.05f * value_noise((p.x() + p.y()) * 60.0f, p.z() * 60.0f, s + 31);
    if (p.z() < 0.08f) return Vec3(0.85f, 0.85f, 0.82f);  // skirting board
    return Vec3(0.70f, 0.66f, 0.60f) * m;
  };
  const AlbedoFn right_wall = [plaster](const Vec3& p) -> Vec3 {
    if (p.y() > kDoorY0 && p.y() < kDoorY1 && p.z() < kDoorZ1) return {0.004f, 0.004f, 0.005f};
    const bool frame =
        p.y() > kDoorY0 - 0.06f && p.y() < kDoorY1 + 0.06f && p.z() < kDoorZ1 + 0.06f;
    return frame ? Vec3(0.86f, 0.86f, 0.84f) : plaster(p);
  };
  const AlbedoFn back_wall = [s, plaster](const Vec3& p) -> Vec3 {
    if (p.x() >= kWinX0 && p.x() <= kWinX1 && p.z() >= kWinZ0 && p.z() <= kWinZ1)
      return in_window_glass(p) ? Vec3::Zero() : Vec3(0.88f, 0.88f, 0.86f);
    if (p.z() < 0.08f) return plaster(p);
    const float m = 0.92f + 0.12f * fbm(p.x() * 2.0f, p.z() * 2.0f, s + 40, 3);
    return Vec3(0.40f, 0.52f, 0.45f) * m;
  };
  const EmissionFn window = [s](const Vec3& p, int) -> Vec3 {
    return in_window_glass(p) ? sky_radiance(p, s) : Vec3::Zero();
  };
  const AlbedoFn ceiling = [s](const Vec3& p) -> Vec3 {
    return Vec3(0.82f, 0.82f, 0.80f) *
           (0.96f + 0.06f * value_noise(p.x() * 20, p.y() * 20, s + 50));
  };
  const EmissionFn lamps = [em](const Vec3& p, int state) -> Vec3 {
    for (const AreaLight* l : {&em.lamp_a, &em.lamp_b}) {
      if (!in_lamp(*l, p)) continue;
      if (l->switch_bit >= 0 && !((state >> l->switch_bit) & 1)) return Vec3::Zero();
      return l->radiance;
    }
    return Vec3::Zero();
  };

  constexpr float kRoomTexel = 0.02f, kRoomLight = 0.1f;
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2, side = f % 2;
    AlbedoFn albedo = plaster;
    EmissionFn emission;
    if (axis == 2) albedo = side ? ceiling : floor;
    if (axis == 0 && side == 1) albedo = right_wall;
    if (axis == 2 && side == 1) emission = lamps;
    if (axis == 1 && side == 1) {
      albedo = back_wall;
      emission = window;
    }
    room_patch_[f] =
        b.add_face(room_lo_, room_hi_, axis, side, true, kRoomTexel, kRoomLight, albedo, emission);
  }
  // Glass, and the corridor beyond the doorway, give no structured-light depth.
  patches_[room_patch_[3]].no_depth_boxes.push_back(
      {Vec3(kWinX0, 2.5f, kWinZ0), Vec3(kWinX1, 2.5f, kWinZ1)});
  patches_[room_patch_[1]].no_depth_boxes.push_back(
      {Vec3(2.5f, kDoorY0, 0.0f), Vec3(2.5f, kDoorY1, kDoorZ1)});

  // The table: a wooden top on four dark metal legs.
  const AlbedoFn table_wood = [s](const Vec3& p) -> Vec3 {
    const float grain = 0.75f + 0.5f * fbm(p.x() * 2.5f, p.y() * 45.0f + p.z() * 45.0f, s + 60, 4);
    const float ring =
        0.9f + 0.1f * std::sin(40.0f * p.y() + 6.0f * fbm(p.x(), p.y() * 3, s + 61, 2));
    return Vec3(0.58f, 0.38f, 0.22f) * (grain * ring);
  };
  const AlbedoFn metal = [](const Vec3&) -> Vec3 { return {0.07f, 0.07f, 0.08f}; };
  const float top = static_cast<float>(kTableTop);
  const float ay = static_cast<float>(kAnchor.y());  // the table is centred on the anchor
  const Vec3 table_lo(-0.75f, ay - 0.4f, top - 0.03f), table_hi(0.75f, ay + 0.4f, top);
  boxes_.push_back(
      b.add_box(table_lo, table_hi, kAllFaces & ~face_bit(2, 1), 0.01f, 0.05f, table_wood));
  {  // the top face, finer: virtual objects stand on it and their shadows fall on it
    Box& t = boxes_.back();
    t.patch[5] = b.add_face(table_lo, table_hi, 2, 1, false, 0.004f, 0.025f, table_wood);
  }
  for (float lx : {-0.7f, 0.65f})
    for (float ly : {ay - 0.35f, ay + 0.3f})
      boxes_.push_back(b.add_box({lx, ly, 0.0f}, {lx + 0.05f, ly + 0.05f, top - 0.03f},
                                 kAllFaces & ~(face_bit(2, 0) | face_bit(2, 1)), 0.01f, 0.05f,
                                 metal));

  // A red box with a label on the table, left of the anchor.
  const AlbedoFn red_box = [s](const Vec3& p) -> Vec3 {
    const float z = p.z() - static_cast<float>(kTableTop);
    if (z > 0.07f && z < 0.11f) {
      const float ink =
          value_noise(p.x() * 150 + p.y() * 150, z * 150, s + 70) > 0.6f ? 0.2f : 1.0f;
      return Vec3(0.90f, 0.84f, 0.58f) * ink;
    }
    return Vec3(0.62f, 0.07f, 0.05f) *
           (0.9f + 0.2f * value_noise(p.x() * 80, p.y() * 80 + p.z() * 80, s + 71));
  };
  boxes_.push_back(b.add_box({-0.6f, ay + 0.1f, top}, {-0.4f, ay + 0.28f, top + 0.18f},
                             kAllFaces & ~face_bit(2, 0), 0.005f, 0.03f, red_box));

  // A black television on the back wall: too dark for structured light.
  const AlbedoFn black = [](const Vec3&) -> Vec3 { return {0.015f, 0.015f, 0.018f}; };
  boxes_.push_back(b.add_box({-2.0f, 2.45f, 0.9f}, {-0.8f, 2.5f, 1.6f}, kAllFaces & ~face_bit(1, 1),
                             0.01f, 0.1f, black));
  for (int f : boxes_.back().patch)
    if (f >= 0) patches_[f].no_depth = true;

  // A painted cabinet against the left wall and a sofa against the front wall.
  const AlbedoFn cabinet = [s](const Vec3& p) -> Vec3 {
    const bool seam = std::abs(p.y() - 0.25f) < 0.004f || std::abs(p.z() - 0.45f) < 0.004f;
    const bool handle = std::abs(p.y() - 0.2f) < 0.01f && p.z() > 0.55f && p.z() < 0.7f;
    if (handle) return {0.75f, 0.72f, 0.6f};
    return Vec3(0.28f, 0.36f, 0.44f) *
           ((seam ? 0.4f : 1.0f) * (0.95f + 0.1f * value_noise(p.y() * 40, p.z() * 40, s + 80)));
  };
  boxes_.push_back(b.add_box({-2.5f, -0.5f, 0.0f}, {-2.1f, 1.0f, 0.9f},
                             face_bit(0, 1) | face_bit(1, 0) | face_bit(1, 1) | face_bit(2, 1),
                             0.01f, 0.1f, cabinet));
  const AlbedoFn fabric = [s](const Vec3& p) -> Vec3 {
    const float weave = 0.8f + 0.25f * value_noise(p.x() * 200, (p.y() + p.z()) * 200, s + 90) +
                        0.1f * fbm(p.x() * 5, (p.y() + p.z()) * 5, s + 91, 2);
    return Vec3(0.60f, 0.44f, 0.14f) * weave;
  };
  boxes_.push_back(b.add_box({-1.0f, -2.5f, 0.0f}, {1.0f, -1.75f, 0.45f},
                             face_bit(0, 0) | face_bit(0, 1) | face_bit(1, 1) | face_bit(2, 1),
                             0.01f, 0.1f, fabric));
  boxes_.push_back(b.add_box({-1.0f, -2.5f, 0.45f}, {1.0f, -2.3f, 0.85f},
                             face_bit(0, 0) | face_bit(0, 1) | face_bit(1, 1) | face_bit(2, 1),
                             0.01f, 0.1f, fabric));

  // A mirror ball right of the anchor: reflections for the light estimate, no depth.
  spheres_.push_back({{0.45f, ay + 0.15f, top + 0.07f}, 0.07f, Vec3(0.85f, 0.85f, 0.86f)});

  for (std::size_t i = 0; i < boxes_.size(); ++i)
    static_prims_.push_back({PrimRef::Kind::Box, static_cast<std::uint8_t>(i)});
  for (std::size_t i = 0; i < spheres_.size(); ++i)
    static_prims_.push_back({PrimRef::Kind::Sphere, static_cast<std::uint8_t>(i)});

  lights_ = {em.lamp_a, em.lamp_b, em.window};
}

}  // namespace probeless::sim

namespace probeless::sim {

namespace {

// Whether p lies inside one of the boxes (under an object standing on a surface).
bool inside_any(const std::vector<Box>& boxes, const Vec3& p) {
  for (const Box& b : boxes)
    if ((p.array() > b.lo.array()).all() && (p.array() < b.hi.array()).all()) return true;
  return false;
}

// Whether anything static blocks the segment from r.o to r.o + t_max r.d.
bool occluded(const Ray& r, const SimWorld& w, float t_max) {
  for (const Box& b : w.boxes()) {
    Hit h;
    h.t = t_max;
    if (hit_box(r, b, h)) return true;
  }
  for (const Sphere& s : w.spheres()) {
    float t;
    if (hit_sphere(r, s.centre, s.radius, t) && t < t_max) return true;
  }
  return false;
}

float luminance(const Vec3& c) {
  return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z();
}

// The lighting grid of one patch: per light, the irradiance at each node (cell centres).
struct LightGrid {
  int nu = 0, nv = 0;
  std::vector<std::vector<Vec3>> irradiance;  // [light][j * nu + i]
  std::vector<float> ao;
  std::vector<std::uint8_t> hidden;  // inside an object: no light of its own
  // Hidden nodes take the mean of their visible (or already filled) 8-neighbours, ring by
  // ring inwards.
  void fill_hidden() {
    for (bool changed = true; changed;) {
      changed = false;
      std::vector<std::uint8_t> next = hidden;
      for (int j = 0; j < nv; ++j) {
        for (int i = 0; i < nu; ++i) {
          const std::size_t k = static_cast<std::size_t>(j) * nu + i;
          if (!hidden[k]) continue;
          int n = 0;
          std::vector<Vec3> sum(irradiance.size(), Vec3::Zero());
          float ao_sum = 0;
          for (int dj = -1; dj <= 1; ++dj) {
            for (int di = -1; di <= 1; ++di) {
              const int ii = i + di, jj = j + dj;
              if (ii < 0 || jj < 0 || ii >= nu || jj >= nv) continue;
              const std::size_t q = static_cast<std::size_t>(jj) * nu + ii;
              if (hidden[q]) continue;
              ++n;
              ao_sum += ao[q];
              for (std::size_t l = 0; l < irradiance.size(); ++l) sum[l] += irradiance[l][q];
            }
          }
          if (n == 0) continue;
          for (std::size_t l = 0; l < irradiance.size(); ++l)
            irradiance[l][k] = sum[l] / static_cast<float>(n);
          ao[k] = ao_sum / n;
          next[k] = 0;
          changed = true;
        }
      }
      hidden = std::move(next);
    }
  }
  Vec3 node(const Patch& p, int i, int j) const {
    return p.origin + ((i + 0.5f) / nu * p.size_u) * p.u + ((j + 0.5f) / nv * p.size_v) * p.v;
  }
  Vec3 sample(int light, const Patch& p, const Vec3& x) const {
    const Vec3 rel = x - p.origin;
    const float fu = std::clamp(rel.dot(p.u) / p.size_u * nu - 0.5f, 0.0f, nu - 1.0f);
    const float fv = std::clamp(rel.dot(p.v) / p.size_v * nv - 0.5f, 0.0f, nv - 1.0f);
    const int i = std::min(static_cast<int>(fu), nu - 2),
              j = std::min(static_cast<int>(fv), nv - 2);
    const float a = fu - i, b = fv - j;
    const auto& e = irradiance[light];
    const auto at = [&](int ii, int jj) { return e[static_cast<std::size_t>(jj) * nu + ii]; };
    return (1 - b) * ((1 - a) * at(i, j) + a * at(i + 1, j)) +
           b * ((1 - a) * at(i, j + 1) + a * at(i + 1, j + 1));
  }
};

// Every node uses the same stratified sample positions on each light and the same directions
// (in its own frame): the error is then smooth across a surface instead of blotchy.
constexpr int kLightSamples = 5;  // per axis: 25 samples per light and node
constexpr int kAoSamples = 5;     // per axis: 25 cosine-weighted directions
constexpr float kAoDistance = 1.0f;

}  // namespace

// Radiosity in two parts: direct light from the area lights with shadows (stratified
// Monte Carlo on a coarse grid per patch), and the interreflections as the ambient term of
// progressive radiosity (Cohen et al. 1988): the room's mean reflected radiance summed over
// all bounces, darkened near other surfaces by an obscurance factor. Baked per light, so
// that a lamp state is a sum of tables.
void SimWorld::bake_lighting(const WorldBuilder& builder) {
  const auto& specs = builder.specs();
  const int n_lights = static_cast<int>(lights_.size());
  std::vector<LightGrid> grids(patches_.size());
  for (std::size_t pi = 0; pi < patches_.size(); ++pi) {
    const Patch& p = patches_[pi];
    LightGrid& g = grids[pi];
    const float spacing = specs[pi].light_spacing;
    g.nu = std::max(2, static_cast<int>(std::ceil(p.size_u / spacing)));
    g.nv = std::max(2, static_cast<int>(std::ceil(p.size_v / spacing)));
    g.irradiance.assign(n_lights,
                        std::vector<Vec3>(static_cast<std::size_t>(g.nu) * g.nv, Vec3::Zero()));
    g.ao.assign(static_cast<std::size_t>(g.nu) * g.nv, 1.0f);
    g.hidden.assign(g.ao.size(), 0);
  }

  // One row of nodes of one patch per work item; every node on its own, so the result does
  // not depend on how the rows are shared out.
  std::vector<std::pair<int, int>> rows;
  for (std::size_t pi = 0; pi < patches_.size(); ++pi)
    for (int j = 0; j < grids[pi].nv; ++j) rows.push_back({static_cast<int>(pi), j});
  WorkerPool pool(2);
  pool.parallel_for(static_cast<int>(rows.size()), [&](int r) {
    const auto [pi, j] = rows[r];
    const Patch& p = patches_[pi];
    LightGrid& g = grids[pi];
    for (int i = 0; i < g.nu; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * g.nu + i;
      const Vec3 origin = g.node(p, i, j) + 1e-3f * p.normal;
      // A node under something standing on the surface (the wall behind the television, the
      // floor under a leg) sees nothing; it is filled from its neighbours below, or the
      // darkness would bleed out around the object.
      if (inside_any(boxes_, origin)) {
        g.hidden[k] = 1;
        continue;
      }
      for (int li = 0; li < n_lights; ++li) {
        const AreaLight& l = lights_[li];
        const float area = 4.0f * l.u_half.norm() * l.v_half.norm();
        Vec3 e = Vec3::Zero();
        for (int s = 0; s < kLightSamples * kLightSamples; ++s) {
          const std::uint64_t h = hash_combine(seed_, li * 64 + s);
          const float su = ((s % kLightSamples) + uniform01(h)) / kLightSamples * 2 - 1;
          const float sv = ((s / kLightSamples) + uniform01(mix64(h))) / kLightSamples * 2 - 1;
          const Vec3 q = l.centre + su * l.u_half + sv * l.v_half;
          const Vec3 to = q - origin;
          const float r2 = to.squaredNorm();
          const Vec3 dir = to / std::sqrt(r2);
          const float cos_x = p.normal.dot(dir), cos_l = -l.normal.dot(dir);
          if (cos_x <= 0 || cos_l <= 0) continue;
          if (occluded(Ray(origin, to), *this, 0.999f)) continue;
          const Vec3 radiance = l.is_window
                                    ? (in_window_glass(q) ? sky_radiance(q, seed_) : Vec3::Zero())
                                    : l.radiance;
          e += radiance * (cos_x * cos_l / r2);
        }
        g.irradiance[li][k] = e * (area / (kLightSamples * kLightSamples));
      }
      // Obscurance: cosine-weighted directions, each counting as open in proportion to how
      // far it travels (up to kAoDistance).
      float open = 0;
      for (int s = 0; s < kAoSamples * kAoSamples; ++s) {
        const std::uint64_t h = hash_combine(seed_, 5000 + s);
        const float e1 = ((s % kAoSamples) + uniform01(h)) / kAoSamples;
        const float e2 = ((s / kAoSamples) + uniform01(mix64(h))) / kAoSamples;
        const float rr = std::sqrt(e1), phi = 2 * kPi * e2;
        const Vec3 d =
            rr * std::cos(phi) * p.u + rr * std::sin(phi) * p.v + std::sqrt(1 - e1) * p.normal;
        const Hit hit = trace(Ray(origin, d), *this, static_prims_, nullptr);
        open += std::min(1.0f, hit.t / kAoDistance);
      }
      g.ao[k] = open / (kAoSamples * kAoSamples);
    }
  });

  double area_sum = 0, albedo_sum = 0;
  std::vector<Vec3> reflected_rgb(n_lights, Vec3::Zero());
  for (std::size_t pi = 0; pi < patches_.size(); ++pi) {
    const Patch& p = patches_[pi];
    LightGrid& g = grids[pi];
    const float node_area = p.size_u * p.size_v / (g.nu * g.nv);
    for (int j = 0; j < g.nv; ++j) {
      for (int i = 0; i < g.nu; ++i) {
        const std::size_t k = static_cast<std::size_t>(j) * g.nu + i;
        if (g.hidden[k]) continue;
        const Vec3 albedo = specs[pi].albedo(g.node(p, i, j));
        area_sum += node_area;
        albedo_sum += node_area * luminance(albedo);
        for (int li = 0; li < n_lights; ++li)
          reflected_rgb[li] += (node_area / kPi) * albedo.cwiseProduct(g.irradiance[li][k]);
      }
    }
    g.fill_hidden();
  }

  // Ambient radiance per light: the mean first-bounce radiance times 1 / (1 - mean albedo)
  // for the later bounces.
  const float mean_albedo = static_cast<float>(albedo_sum / area_sum);
  std::vector<Vec3> ambient_radiance(n_lights);
  for (int li = 0; li < n_lights; ++li)
    ambient_radiance[li] = reflected_rgb[li] / static_cast<float>(area_sum) / (1.0f - mean_albedo);
  for (int state = 0; state < kLampStates; ++state) {
    ambient_[state] = Vec3::Zero();
    for (int li = 0; li < n_lights; ++li) {
      const AreaLight& l = lights_[li];
      if (l.switch_bit < 0 || ((state >> l.switch_bit) & 1))
        ambient_[state] += kPi * ambient_radiance[li];
    }
  }
  for (std::size_t pi = 0; pi < patches_.size(); ++pi) {
    LightGrid& g = grids[pi];
    for (int li = 0; li < n_lights; ++li)
      for (std::size_t k = 0; k < g.ao.size(); ++k)
        g.irradiance[li][k] += (kPi * g.ao[k]) * ambient_radiance[li];
  }

  // The fine textures: albedo x irradiance / pi + emission, per lamp state.
  std::vector<std::pair<int, int>> texel_rows;
  for (std::size_t pi = 0; pi < patches_.size(); ++pi) {
    Patch& p = patches_[pi];
    const std::size_t n = static_cast<std::size_t>(p.nu) * p.nv;
    p.radiance.assign(kLampStates, std::vector<Eigen::Array4f>(n, Eigen::Array4f::Zero()));
    for (int j = 0; j < p.nv; ++j) texel_rows.push_back({static_cast<int>(pi), j});
  }
  pool.parallel_for(static_cast<int>(texel_rows.size()), [&](int r) {
    const auto [pi, j] = texel_rows[r];
    Patch& p = patches_[pi];
    const PatchSpec& spec = specs[pi];
    const LightGrid& g = grids[pi];
    for (int i = 0; i < p.nu; ++i) {
      const Vec3 x = p.origin + ((i + 0.5f) * p.texel) * p.u + ((j + 0.5f) * p.texel) * p.v;
      const Vec3 albedo = spec.albedo(x);
      std::array<Vec3, 8> e_light;
      for (int li = 0; li < n_lights; ++li) e_light[li] = g.sample(li, p, x);
      for (int state = 0; state < kLampStates; ++state) {
        Vec3 e = Vec3::Zero();
        for (int li = 0; li < n_lights; ++li) {
          const AreaLight& l = lights_[li];
          if (l.switch_bit < 0 || ((state >> l.switch_bit) & 1)) e += e_light[li];
        }
        Vec3 radiance = albedo.cwiseProduct(e) / kPi;
        if (spec.emission) radiance += spec.emission(x, state);
        p.radiance[state][static_cast<std::size_t>(j) * p.nu + i] << radiance.x(), radiance.y(),
            radiance.z(), 0.0f;
      }
    }
  });
}

// The truth light: radiance around the probe position, 3 x 3 rays per texel, static scene.
void SimWorld::render_light_probes() {
  constexpr int kFace = 32, kSub = 3;
  const Vec3 origin = light_probe_position().cast<float>();
  for (int state = 0; state < kLampStates; ++state) {
    auto cube = std::make_shared<Cubemap>(kFace);
    for (int f = 0; f < 6; ++f) {
      ImageRGBF& face = cube->faces[f];
      for (int y = 0; y < kFace; ++y) {
        for (int x = 0; x < kFace; ++x) {
          Vec3 sum = Vec3::Zero();
          for (int s = 0; s < kSub * kSub; ++s) {
            const double u = (x + ((s % kSub) + 0.5) / kSub) / kFace;
            const double v = (y + ((s / kSub) + 0.5) / kSub) / kFace;
            const Ray ray(origin, cube_direction(static_cast<CubeFace>(f), u, v).cast<float>());
            sum += shade(ray, trace_all(ray, *this, nullptr), *this, state, nullptr);
          }
          for (int c = 0; c < 3; ++c) face.at(x, y, c) = sum[c] / (kSub * kSub);
        }
      }
    }
    light_[state] = std::move(cube);
  }
}

int SimWorld::lamp_state(double t) {
  const double phase = std::fmod(t, kLampPeriod);
  return (phase >= 0 && phase < 0.5 * kLampPeriod) ? 1 : 0;
}

Pose SimWorld::rig_pose(TrajectoryKind kind, double t) const {
  double theta = 0;
  if (kind == TrajectoryKind::Orbit) theta = 2 * std::numbers::pi * t / kOrbitPeriod;
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
  o.capsules[0] = {fingers.cast<float>(), hand.cast<float>(), 0.04f};
  o.capsules[1] = {hand.cast<float>(), elbow.cast<float>(), 0.045f};
  o.capsules[2] = {elbow.cast<float>(), shoulder.cast<float>(), 0.055f};
  return o;
}

Eigen::Vector3d object_anchor() {
  return kAnchor;
}
double table_top_height_m() {
  return kTableTop;
}
Eigen::Vector3d light_probe_position() {
  return kAnchor + Eigen::Vector3d(0, 0, 0.1);
}

}  // namespace probeless::sim
