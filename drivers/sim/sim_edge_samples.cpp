// SimRenderer's mixed pixels at silhouettes (SimOptions::edge_samples): a real camera's pixel
// integrates light over its footprint, so where a hand's outline crosses it the pixel holds
// hand and wall in proportion. One ray per pixel gives hard silhouettes, where estimating the
// foreground colour at a soft matte (docs/compositing.md) has nothing to undo.
#include <algorithm>
#include <cmath>

#include "drivers/sim/sim_renderer.hpp"
#include "drivers/sim/sim_trace.hpp"

namespace probeless::sim {

namespace {

bool jump(float a, float b) {
  return std::fabs(a - b) > SimRenderer::kEdgeJump * std::min(a, b);
}

}  // namespace

void SimRenderer::supersample_edges(const Eigen::Matrix3f& rotation, const Eigen::Vector3f& origin,
                                    int lamp_state, const Occluder* occluder) {
  const int n = edge_samples_, tiles_x = (width_ + kTile - 1) / kTile;
  const SimWorld& w = *world_;
  const float inv_fx = static_cast<float>(1.0 / fx_), inv_fy = static_cast<float>(1.0 / fy_);
  // Bands of rows, each with its own list, joined in order: the same frame for any thread
  // count (docs/sim.md, "threads").
  constexpr int kRowsPerTask = 16;
  const int tasks = (height_ + kRowsPerTask - 1) / kRowsPerTask;
  std::vector<std::vector<EdgePixel>> found(static_cast<std::size_t>(tasks));
  const auto band = [&](int task) {
    std::vector<float> depth(static_cast<std::size_t>(n) * n);
    std::vector<Eigen::Vector3f> radiance(depth.size());
    const int y0 = task * kRowsPerTask, y1 = std::min(height_, y0 + kRowsPerTask);
    for (int y = y0; y < y1; ++y) {
      for (int x = 0; x < width_; ++x) {
        const float d = depth_.at(x, y);
        const bool edge = (x > 0 && jump(d, depth_.at(x - 1, y))) ||
                          (x + 1 < width_ && jump(d, depth_.at(x + 1, y))) ||
                          (y > 0 && jump(d, depth_.at(x, y - 1))) ||
                          (y + 1 < height_ && jump(d, depth_.at(x, y + 1)));
        if (!edge) continue;
        const TileList& list = lists_[static_cast<std::size_t>(y / kTile) * tiles_x +
                                      static_cast<std::size_t>(x / kTile)];
        const std::span<const PrimRef> prims(list.prims.data(), list.count);
        float lo = std::numeric_limits<float>::infinity(), hi = 0;
        Eigen::Vector3f mean = Eigen::Vector3f::Zero();
        for (int j = 0; j < n; ++j) {
          for (int i = 0; i < n; ++i) {
            // Stratified centres of an n x n grid over the footprint [x - 0.5, x + 0.5).
            const float xn = (x - 0.5f + (i + 0.5f) / n - static_cast<float>(cx_)) * inv_fx;
            const float yn = (y - 0.5f + (j + 0.5f) / n - static_cast<float>(cy_)) * inv_fy;
            const Ray ray(origin, rotation.col(0) * xn + rotation.col(1) * yn + rotation.col(2));
            const Hit hit = trace(ray, w, prims, occluder);
            const std::size_t k = static_cast<std::size_t>(j) * n + i;
            depth[k] = hit.t;
            radiance[k] = shade(ray, hit, w, lamp_state, occluder);
            mean += radiance[k];
            lo = std::min(lo, hit.t);
            hi = std::max(hi, hit.t);
          }
        }
        const auto count = static_cast<float>(depth.size());
        float* rad = radiance_.row(y) + 3 * x;
        for (int c = 0; c < 3; ++c) rad[c] = mean[c] / count;
        if (!jump(lo, hi)) continue;  // one surface under the footprint: averaged, not mixed
        const float split = 0.5f * (lo + hi);
        EdgePixel e{y * width_ + x, 0, Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero(), 0, 0};
        int near = 0;
        for (std::size_t k = 0; k < depth.size(); ++k) {
          if (depth[k] < split) {
            ++near;
            e.near_radiance += radiance[k];
            e.near_depth += depth[k];
          } else {
            e.far_radiance += radiance[k];
            e.far_depth += depth[k];
          }
        }
        const int far = static_cast<int>(depth.size()) - near;  // both >= 1: lo < split <= hi
        e.near_coverage = static_cast<float>(near) / count;
        e.near_radiance /= static_cast<float>(near);
        e.near_depth /= static_cast<float>(near);
        e.far_radiance /= static_cast<float>(far);
        e.far_depth /= static_cast<float>(far);
        found[static_cast<std::size_t>(task)].push_back(e);
      }
    }
  };
  if (pool_) {
    pool_->parallel_for(tasks, band);
  } else {
    for (int t = 0; t < tasks; ++t) band(t);
  }
  for (const auto& f : found) edge_pixels_.insert(edge_pixels_.end(), f.begin(), f.end());
}

}  // namespace probeless::sim
