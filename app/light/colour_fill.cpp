#include "app/light/colour_fill.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace probeless::light {
namespace {

// A colour sample seen from the environment's position: its texel at the finest level, its
// distance and its radiance.
struct Sample {
  int face, x, y;
  float distance;
  std::array<float, 3> radiance;
  bool clipped;  // a channel at the colour camera's top: the radiance is only a lower bound
};

// One level of 2^k x 2^k texel blocks: per block the nearest sample's distance, then the
// radiance sums and counts of the samples near that surface.
struct Level {
  int n = 0, shift = 0;
  std::vector<float> nearest;
  std::vector<std::array<double, 5>> sums;  // r, g, b and count of unclipped; clipped count
  Level(int face, int k)
      : n(face >> k),
        shift(k),
        nearest(static_cast<std::size_t>(6 * n * n), std::numeric_limits<float>::infinity()),
        sums(static_cast<std::size_t>(6 * n * n)) {}
  std::size_t index(int face, int x, int y) const {
    return static_cast<std::size_t>((face * n + (y >> shift)) * n + (x >> shift));
  }
};

}  // namespace

ColourFillStats fill_from_colour(envmap::ImageRGBAF& texels, const Eigen::Vector3d& where,
                                 const RgbdFrame& frame, const PinholeIntrinsics& k,
                                 const Pose& T_world_camera, const Eigen::Vector3d& e,
                                 const ColourFillParams& p) {
  if (frame.color.width() != k.width || frame.color.height() != k.height ||
      frame.depth.width() != k.width || frame.depth.height() != k.height)
    throw std::invalid_argument("colour fill: colour and depth must be the intrinsics' size");
  if (p.stride < 1 || p.max_level < 0)
    throw std::invalid_argument("colour fill: stride must be >= 1 and max_level >= 0");
  const int n = envmap::face_size_of(texels);
  float linear[256];
  for (int i = 0; i < 256; ++i) linear[i] = static_cast<float>(std::pow(i / 255.0, p.gamma));

  ColourFillStats stats;
  std::vector<Sample> samples;
  const Eigen::Matrix3d R = T_world_camera.rotation.toRotationMatrix();
  const Eigen::Vector3d origin = T_world_camera.translation - where;
  for (int v = 0; v < k.height; v += p.stride)
    for (int u = 0; u < k.width; u += p.stride) {
      const std::uint16_t z_mm = frame.depth.at(u, v, 0);
      if (z_mm == 0) continue;
      const std::uint8_t* c = &frame.color.at(u, v, 0);
      const double z = z_mm * 1e-3;
      const Eigen::Vector3d X((u - k.cx) / k.fx * z, (v - k.cy) / k.fy * z, z);
      const Eigen::Vector3f d = (origin + R * X).cast<float>();
      if (d.squaredNorm() < 1e-8f) continue;
      const envmap::CubeCoord cc = envmap::cube_coord_of(d);
      Sample s;
      s.face = cc.face;
      s.x = std::clamp(static_cast<int>(cc.u * static_cast<float>(n)), 0, n - 1);
      s.y = std::clamp(static_cast<int>(cc.v * static_cast<float>(n)), 0, n - 1);
      s.distance = d.norm();
      for (int ch = 0; ch < 3; ++ch) s.radiance[ch] = linear[c[ch]] * static_cast<float>(e[ch]);
      s.clipped =
          c[0] >= p.colour_saturated || c[1] >= p.colour_saturated || c[2] >= p.colour_saturated;
      samples.push_back(s);
    }
  for (const Sample& s : samples) ++(s.clipped ? stats.clipped : stats.samples);

  // Per level, only the samples on the nearest surface of each block count: the colour
  // camera sees past the table's edge to the floor, which the environment's position does
  // not (the table hides it), so a far sample in a block that also holds a near one is
  // occluded there.
  std::vector<Level> levels;
  for (int lv = 0; lv <= p.max_level && (n >> lv) >= 1 && (lv == 0 || (n >> (lv - 1)) % 2 == 0);
       ++lv) {
    Level level(n, lv);
    for (const Sample& s : samples) {
      float& nearest = level.nearest[level.index(s.face, s.x, s.y)];
      nearest = std::min(nearest, s.distance);
    }
    for (const Sample& s : samples) {
      const std::size_t i = level.index(s.face, s.x, s.y);
      if (s.distance > p.surface_ratio * level.nearest[i]) continue;
      if (s.clipped) {
        level.sums[i][4] += 1;
        continue;
      }
      for (int ch = 0; ch < 3; ++ch) level.sums[i][ch] += s.radiance[ch];
      level.sums[i][3] += 1;
    }
    levels.push_back(std::move(level));
  }

  for (int face = 0; face < 6; ++face)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        float* t = &texels.at(x, face * n + y, 0);
        const bool below = p.replace_below_horizon &&
                           envmap::cube_face_direction(
                               face, (static_cast<float>(x) + 0.5f) / static_cast<float>(n),
                               (static_cast<float>(y) + 0.5f) / static_cast<float>(n))
                                   .z() < 0.0f;
        if (t[3] > 0 && !below) continue;  // the fisheye's value stays
        const std::array<double, 5>* cell = nullptr;
        // Above the horizon only near samples: a coarse block there mixes the wall around
        // an unobserved texel (ColourFillParams::levels_above_horizon).
        const std::size_t top =
            below ? levels.size()
                  : std::min(levels.size(), static_cast<std::size_t>(p.levels_above_horizon));
        for (std::size_t lv = 0; lv < top && !cell; ++lv) {
          const auto& c = levels[lv].sums[levels[lv].index(face, x, y)];
          if (c[3] + c[4] > 0) cell = &c;
        }
        // Where the colour camera clipped (a window, a lamp), its samples only bound the
        // radiance from below, and the unclipped ones beside them are the darker frame: the
        // fisheye's bracketed value stays.
        if (!cell || (*cell)[4] > 0) continue;
        for (int ch = 0; ch < 3; ++ch) t[ch] = static_cast<float>((*cell)[ch] / (*cell)[3]);
        t[3] = p.filled_alpha;
        ++stats.filled_texels;
      }
  return stats;
}

}  // namespace probeless::light
