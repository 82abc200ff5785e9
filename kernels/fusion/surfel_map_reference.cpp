#include "kernels/fusion/surfel_map_reference.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace probeless::fusion {
namespace {

constexpr float kSqrt2 = 1.41421356f;

struct Camera {  // the intrinsics as floats, and the frame's pose both ways
  float fx, fy, cx, cy;
  Eigen::Matrix3f R_wc, R_cw;
  Eigen::Vector3f t_wc, t_cw;
  Eigen::Vector3f ray(float x, float y, float z) const {
    return {(x - cx) * z / fx, (y - cy) * z / fy, z};
  }
};

// Millimetres to metres; 0 stays 0 (no depth).
float metres(const DepthImage& depth, int x, int y) {
  return depth.at(x, y) * 0.001f;
}

// The nearest observed depth in the 3 x 3 pixels around (x, y), 0 if none: a surfel on a
// silhouette may land one pixel off its own surface, and that is not free space (6.2.6).
float nearest_around(const DepthImage& depth, int x, int y) {
  float nearest = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (!depth.contains(x + dx, y + dy)) continue;
      const float z = metres(depth, x + dx, y + dy);
      if (z > 0 && (nearest == 0 || z < nearest)) nearest = z;
    }
  return nearest;
}

// Depth for the normals (positions keep the raw depth, as ElasticFusion does with its
// bilateral filter): the mean over (2 r + 1)^2 pixels of the depths on the centre's side of
// any silhouette; 0 where there is no depth.
float smoothed_depth(const DepthImage& depth, int x, int y, int r, float discontinuity_ratio) {
  const float z = metres(depth, x, y);
  if (z == 0) return 0;
  const float jump = discontinuity_ratio * z;
  float sum = 0;
  int n = 0;
  for (int dy = std::max(-r, -y); dy <= std::min(r, depth.height() - 1 - y); ++dy)
    for (int dx = std::max(-r, -x); dx <= std::min(r, depth.width() - 1 - x); ++dx) {
      const float zn = metres(depth, x + dx, y + dy);
      if (zn != 0 && std::abs(zn - z) <= jump) {
        sum += zn;
        ++n;
      }
    }
  return sum / static_cast<float>(n);
}
}  // namespace

SurfelMap::SurfelMap(SurfelMapParams params) : params_(params) {
  check_surfel_map_params(params_, "SurfelMap");
  for (int v = 0; v < 256; ++v) linear_[v] = static_cast<float>(std::pow(v / 255.0, params_.gamma));
}

std::size_t SurfelMap::stable_count() const {
  return static_cast<std::size_t>(std::count_if(surfels_.begin(), surfels_.end(),
                                                [&](const Surfel& s) { return is_stable(s); }));
}

SurfelIntegrationStats SurfelMap::integrate(const DepthImage& depth, const ImageRGB8& colour,
                                            const std::array<float, 3>& radiance_per_unit,
                                            const PinholeIntrinsics& k, const Pose& T_world_camera,
                                            std::int64_t frame_index) {
  check_surfel_frame("SurfelMap", depth.width(), depth.height(), colour.width(), colour.height(),
                     radiance_per_unit, k);

  const SurfelMapParams& p = params_;
  const int W = k.width, H = k.height, S = p.index_scale;
  const std::size_t IW = static_cast<std::size_t>(W) * S, IH = static_cast<std::size_t>(H) * S;
  if (index_map_.size() != IW * IH) {
    index_map_.assign(IW * IH, 0);
    touched_cells_.clear();
  }
  for (std::uint32_t cell : touched_cells_) index_map_[cell] = 0;
  touched_cells_.clear();

  Camera cam{static_cast<float>(k.fx),
             static_cast<float>(k.fy),
             static_cast<float>(k.cx),
             static_cast<float>(k.cy),
             T_world_camera.rotation.toRotationMatrix().cast<float>(),
             {},
             T_world_camera.translation.cast<float>(),
             {}};
  cam.R_cw = cam.R_wc.transpose();
  cam.t_cw = -(cam.R_cw * cam.t_wc);

  SurfelIntegrationStats stats;
  const std::size_t existing = surfels_.size();
  std::vector<std::uint8_t> remove(existing, 0);
  camera_z_.assign(existing, 0);

  // The index map from this frame's pose, one cell per surfel, the nearest winning; and the
  // depth violations (6.2.6), which we remove outright rather than lower their confidence: a
  // surfel the sensor now sees through is free space, and the judge's removal_s wants it gone
  // in the next snapshot, not after it has decayed below the stable threshold.
  for (std::size_t i = 0; i < existing; ++i) {
    const Eigen::Vector3f pc = cam.R_cw * surfels_[i].position + cam.t_cw;
    if (pc.z() <= 0) continue;
    const float u = cam.fx * pc.x() / pc.z() + cam.cx, v = cam.fy * pc.y() / pc.z() + cam.cy;
    // Pixel x covers [x - 0.5, x + 0.5): cells S x .. S x + S - 1.
    const float cu = std::floor((u + 0.5f) * S), cv = std::floor((v + 0.5f) * S);
    if (cu < 0 || cv < 0 || cu >= static_cast<float>(IW) || cv >= static_cast<float>(IH)) continue;
    const auto ix = static_cast<std::size_t>(cu), iy = static_cast<std::size_t>(cv);
    const int px = static_cast<int>(ix) / S, py = static_cast<int>(iy) / S;
    if (depth.at(px, py) != 0) {
      const float nearest = nearest_around(depth, px, py);
      if (pc.z() < nearest - p.violation_margin_m) {
        remove[i] = 1;
        ++stats.removed_violation;
        continue;
      }
    }
    camera_z_[i] = pc.z();
    const std::size_t cell = iy * IW + ix;
    const std::uint32_t current = index_map_[cell];
    if (current == 0) touched_cells_.push_back(static_cast<std::uint32_t>(cell));
    if (current == 0 || pc.z() < camera_z_[current - 1])
      index_map_[cell] = static_cast<std::uint32_t>(i + 1);
  }

  // Depth for the normals only, smoothed on first use: only pixels near the region cost.
  smoothed_.assign(static_cast<std::size_t>(W) * H, -1.0f);
  const auto smoothed = [&](int x, int y) {
    float& out = smoothed_[static_cast<std::size_t>(y) * W + x];
    if (out < 0) out = smoothed_depth(depth, x, y, p.normal_smoothing_px, p.discontinuity_ratio);
    return out;
  };

  const float f_mean = 0.5f * (cam.fx + cam.fy);
  const float half_diagonal = 0.5f * std::hypot(static_cast<float>(W), static_cast<float>(H));
  const float cos_normal = std::cos(p.normal_tolerance_rad);
  const float region_r2 = p.region_radius_m * p.region_radius_m;
  const int step = p.normal_step_px;
  for (int y = step; y < H - step; ++y) {
    for (int x = step; x < W - step; ++x) {
      const float z = metres(depth, x, y);
      if (z < p.min_depth_m || z > p.max_depth_m) continue;
      const Eigen::Vector3f pc = cam.ray(static_cast<float>(x), static_cast<float>(y), z);
      const Eigen::Vector3f pw = cam.R_wc * pc + cam.t_wc;
      if ((pw - p.region_centre).squaredNorm() > region_r2) continue;

      // The normal from the smoothed depth neighbours' cross product (6.2.2); none across a
      // silhouette.
      const float zs = smoothed(x, y), zl = smoothed(x - step, y), zr = smoothed(x + step, y);
      const float zu = smoothed(x, y - step), zd = smoothed(x, y + step);
      const float jump = p.discontinuity_ratio * zs;
      if (zs == 0 || std::abs(zl - zs) > jump || std::abs(zr - zs) > jump ||
          std::abs(zu - zs) > jump || std::abs(zd - zs) > jump)
        continue;
      const auto fx = static_cast<float>(x), fy = static_cast<float>(y),
                 fs = static_cast<float>(step);
      Eigen::Vector3f n = (cam.ray(fx + fs, fy, zr) - cam.ray(fx - fs, fy, zl))
                              .cross(cam.ray(fx, fy + fs, zd) - cam.ray(fx, fy - fs, zu));
      const float n_len = n.norm();
      if (!(n_len > 0)) continue;
      n /= n_len;
      if (n.dot(pc) > 0) n = -n;  // towards the camera
      ++stats.candidates;

      const std::uint8_t* rgb = &colour.at(x, y);
      std::uint8_t flags = 0;
      if (rgb[0] >= p.saturated_level || rgb[1] >= p.saturated_level || rgb[2] >= p.saturated_level)
        flags |= kBornSaturated;
      else if (rgb[0] < p.black_level && rgb[1] < p.black_level && rgb[2] < p.black_level)
        flags |= kBornBlack;
      const std::array<float, 3> radiance{linear_[rgb[0]] * radiance_per_unit[0],
                                          linear_[rgb[1]] * radiance_per_unit[1],
                                          linear_[rgb[2]] * radiance_per_unit[2]};
      const float g = std::hypot(fx - cam.cx, fy - cam.cy) / half_diagonal;
      const float weight = std::exp(-g * g / (2 * p.radial_sigma * p.radial_sigma));
      const float colour_weight = flags ? weight * p.clipped_weight_scale : weight;
      const float radius =
          kSqrt2 * z / f_mean / std::max(std::abs(n.z()), 1.0f / p.max_radius_factor);
      const Eigen::Vector3f nw = cam.R_wc * n;

      // Correspondence (6.2.2): the pixel's S x S cells of the index map; the closest depth
      // within the tolerance whose normal agrees.
      std::int64_t best = -1;
      float best_dz = p.depth_tolerance_m;
      for (int cy = y * S; cy < (y + 1) * S; ++cy)
        for (int cx = x * S; cx < (x + 1) * S; ++cx) {
          const std::uint32_t id = index_map_[static_cast<std::size_t>(cy) * IW + cx];
          if (id == 0) continue;
          const float dz = std::abs(camera_z_[id - 1] - z);
          if (dz >= best_dz || surfels_[id - 1].normal.dot(nw) < cos_normal) continue;
          best = id - 1;
          best_dz = dz;
        }

      if (best >= 0) {  // confidence-weighted average (6.2.2)
        Surfel& s = surfels_[static_cast<std::size_t>(best)];
        const float c = s.confidence, sum = c + weight, colour_sum = c + colour_weight;
        s.position = (c * s.position + weight * pw) / sum;
        s.normal = (c * s.normal + weight * nw).normalized();
        s.radius = (c * s.radius + weight * radius) / sum;
        for (int ch = 0; ch < 3; ++ch)
          s.radiance[ch] = (c * s.radiance[ch] + colour_weight * radiance[ch]) / colour_sum;
        s.confidence = sum;
        s.last_seen_frame = frame_index;
        ++stats.fused;
      } else {  // a new, unstable surfel; clipped pixels start lower (6.2.2)
        surfels_.push_back(
            {pw, nw, radius, colour_weight, radiance, flags, frame_index, frame_index});
        ++stats.born;
      }
    }
  }

  // Unstable surfels that stopped being seen (6.2.2, 6.2.6), and the violations found above.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < surfels_.size(); ++i) {
    const Surfel& s = surfels_[i];
    const bool stale =
        !is_stable(s) && frame_index - s.last_seen_frame > p.unstable_max_unseen_frames;
    if (i < existing && remove[i]) continue;
    if (stale) {
      ++stats.removed_unstable;
      continue;
    }
    surfels_[kept++] = s;
  }
  surfels_.resize(kept);

  // The budget: farthest shell from the virtual content first, then the least confident, then
  // the newest (a total order, so the reference and a kernel can agree exactly).
  if (surfels_.size() > p.max_surfels) {
    const std::size_t excess = surfels_.size() - p.max_surfels;
    std::vector<std::uint32_t> order(surfels_.size());
    std::iota(order.begin(), order.end(), 0u);
    std::vector<std::int32_t> shell(surfels_.size());
    for (std::size_t i = 0; i < surfels_.size(); ++i)
      shell[i] = static_cast<std::int32_t>(
          std::floor((surfels_[i].position - p.region_centre).norm() / p.eviction_shell_m));
    const auto evict_first = [&](std::uint32_t a, std::uint32_t b) {
      if (shell[a] != shell[b]) return shell[a] > shell[b];
      if (surfels_[a].confidence != surfels_[b].confidence)
        return surfels_[a].confidence < surfels_[b].confidence;
      return a > b;
    };
    std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(excess),
                     order.end(), evict_first);
    std::vector<std::uint8_t> evict(surfels_.size(), 0);
    for (std::size_t j = 0; j < excess; ++j) evict[order[j]] = 1;
    kept = 0;
    for (std::size_t i = 0; i < surfels_.size(); ++i)
      if (!evict[i]) surfels_[kept++] = surfels_[i];
    surfels_.resize(kept);
    stats.evicted = excess;
  }
  return stats;
}

}  // namespace probeless::fusion
