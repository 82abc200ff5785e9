#include "kernels/light/colour_fill.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace probeless::light {

// A colour sample seen from the environment's position: its texel at the finest level, its
// distance and its radiance.
struct ColourFill::Sample {
  int face, x, y;
  float distance;
  std::array<float, 3> radiance;
  bool clipped;  // a channel at the colour camera's top: the radiance is only a lower bound
};

// One level of 2^k x 2^k texel blocks: per block the nearest sample's distance, then the
// radiance sums and counts of the samples near that surface. Kept between calls: allocating
// them for every snapshot (7 MB at 192 px faces) cost page faults on every publish.
struct ColourFill::Level {
  struct Cell {
    float r = 0, g = 0, b = 0;
    int count = 0, clipped = 0;  // unclipped samples (in r, g, b), clipped ones
  };
  int n = 0, shift = 0;
  std::vector<float> nearest;
  std::vector<Cell> sums;
  void reset(int face, int k) {
    n = face >> k;
    shift = k;
    const auto cells = static_cast<std::size_t>(6 * n * n);
    nearest.assign(cells, std::numeric_limits<float>::infinity());
    sums.assign(cells, Cell{});
  }
  std::size_t index(int face, int x, int y) const {
    return static_cast<std::size_t>((face * n + (y >> shift)) * n + (x >> shift));
  }
};

ColourFill::ColourFill(ColourFillParams params) : params_(params) {
  if (params_.stride < 1 || params_.max_level < 0)
    throw std::invalid_argument("colour fill: stride must be >= 1 and max_level >= 0");
  for (int i = 0; i < 256; ++i)
    linear_[static_cast<std::size_t>(i)] = static_cast<float>(std::pow(i / 255.0, params_.gamma));
}

ColourFill::~ColourFill() = default;

void ColourFill::collect_samples(const RgbdFrame& frame, const PinholeIntrinsics& k,
                                 const Eigen::Vector3d& where, const Pose& T_world_camera,
                                 const Eigen::Vector3d& e, int n) {
  const ColourFillParams& p = params_;
  samples_.clear();
  const Eigen::Matrix3d R = T_world_camera.rotation.toRotationMatrix();
  const Eigen::Vector3d origin = T_world_camera.translation - where;
  for (int v = 0; v < k.height; v += p.stride)
    for (int u = 0; u < k.width; u += p.stride) {
      const std::uint16_t z_mm = frame.depth.at(u, v, 0);
      if (z_mm == 0) continue;
      const std::uint8_t* c = &frame.colour.at(u, v, 0);
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
      for (int ch = 0; ch < 3; ++ch) s.radiance[ch] = linear_[c[ch]] * static_cast<float>(e[ch]);
      s.clipped =
          c[0] >= p.colour_saturated || c[1] >= p.colour_saturated || c[2] >= p.colour_saturated;
      samples_.push_back(s);
    }
}

// Per level, only the samples on the nearest surface of each block count: the colour camera
// sees past the table's edge to the floor, which the environment's position does not (the
// table hides it), so a far sample in a block that also holds a near one is occluded there.
std::size_t ColourFill::sum_levels(int n) {
  std::size_t count = 0;
  for (int lv = 0;
       lv <= params_.max_level && (n >> lv) >= 1 && (lv == 0 || (n >> (lv - 1)) % 2 == 0); ++lv)
    ++count;
  if (levels_.size() < count) levels_.resize(count);
  for (std::size_t lv = 0; lv < count; ++lv) {
    Level& level = levels_[lv];
    level.reset(n, static_cast<int>(lv));
    for (const Sample& s : samples_) {
      float& nearest = level.nearest[level.index(s.face, s.x, s.y)];
      nearest = std::min(nearest, s.distance);
    }
    for (const Sample& s : samples_) {
      const std::size_t i = level.index(s.face, s.x, s.y);
      if (s.distance > params_.surface_ratio * level.nearest[i]) continue;
      Level::Cell& cell = level.sums[i];
      if (s.clipped) {
        ++cell.clipped;
        continue;
      }
      cell.r += s.radiance[0];
      cell.g += s.radiance[1];
      cell.b += s.radiance[2];
      ++cell.count;
    }
  }
  return count;
}

ColourFillStats ColourFill::fill(envmap::ImageRGBAF& texels, const Eigen::Vector3d& where,
                                 const RgbdFrame& frame, const PinholeIntrinsics& k,
                                 const Pose& T_world_camera, const Eigen::Vector3d& e) {
  if (frame.colour.width() != k.width || frame.colour.height() != k.height ||
      frame.depth.width() != k.width || frame.depth.height() != k.height)
    throw std::invalid_argument("colour fill: colour and depth must be the intrinsics' size");
  const ColourFillParams& p = params_;
  const int n = envmap::face_size_of(texels);
  ColourFillStats stats;
  collect_samples(frame, k, where, T_world_camera, e, n);
  for (const Sample& s : samples_) ++(s.clipped ? stats.clipped : stats.samples);
  const std::size_t levels = sum_levels(n);

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
        const Level::Cell* cell = nullptr;
        // Above the horizon only near samples: a coarse block there mixes the wall around
        // an unobserved texel (ColourFillParams::levels_above_horizon).
        const std::size_t top =
            below ? levels : std::min(levels, static_cast<std::size_t>(p.levels_above_horizon));
        for (std::size_t lv = 0; lv < top && !cell; ++lv) {
          const Level::Cell& c = levels_[lv].sums[levels_[lv].index(face, x, y)];
          if (c.count + c.clipped > 0) cell = &c;
        }
        // Where the colour camera clipped (a window, a lamp), its samples only bound the
        // radiance from below, and the unclipped ones beside them are the darker frame: the
        // fisheye's bracketed value stays.
        if (!cell || cell->clipped > 0) continue;
        const auto count = static_cast<float>(cell->count);
        t[0] = cell->r / count;
        t[1] = cell->g / count;
        t[2] = cell->b / count;
        t[3] = p.filled_alpha;
        ++stats.filled_texels;
      }
  return stats;
}

ColourFillStats fill_from_colour(envmap::ImageRGBAF& texels, const Eigen::Vector3d& where,
                                 const RgbdFrame& frame, const PinholeIntrinsics& k,
                                 const Pose& T_world_camera, const Eigen::Vector3d& e,
                                 const ColourFillParams& params) {
  return ColourFill(params).fill(texels, where, frame, k, T_world_camera, e);
}

}  // namespace probeless::light
