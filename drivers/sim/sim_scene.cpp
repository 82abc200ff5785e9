#include "drivers/sim/sim_scene.hpp"

#include <algorithm>
#include <cmath>

#include "drivers/sim/sim_board.hpp"
#include "drivers/sim/sim_random.hpp"

namespace probeless::sim {

namespace {

using Vec3 = Eigen::Vector3f;

// The room and what stands in it (metres, world z up); docs/sim.md has a plan view. The table
// is centred on object_anchor().
const Vec3 kRoomLo{-2.5f, -2.5f, 0.0f};
const Vec3 kRoomHi{2.5f, 2.5f, 2.7f};

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
              -1};
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
              -1};
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
  const float top = static_cast<float>(table_top_height_m());
  const float ay = static_cast<float>(object_anchor().y());  // the table is centred on the anchor
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
    const float z = p.z() - static_cast<float>(table_top_height_m());
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

  if (board_) {  // the ChArUco card, 1 mm texels: 10 per marker cell
    const BoardCard card = board_card();
    boxes_.push_back(b.add_box(card.lo, card.hi, face_bit(2, 1), 0.001f, 0.025f, board_albedo));
  }

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
  lights_[0].patch = lights_[1].patch = room_patch_[5];  // the ceiling
  lights_[2].patch = room_patch_[3];                     // the back wall
  // The window's mean radiance, for what is lit without the bake (the arm).
  AreaLight& glass = lights_[2];
  constexpr int kGrid = 32;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i)
      glass.radiance += window(glass.centre + ((2 * i + 1.0f) / kGrid - 1) * glass.u_half +
                                   ((2 * j + 1.0f) / kGrid - 1) * glass.v_half,
                               0) /
                        static_cast<float>(kGrid * kGrid);
}

std::array<Eigen::Vector3d, 2> room_bounds() {
  return {kRoomLo.cast<double>(), kRoomHi.cast<double>()};
}

}  // namespace probeless::sim
