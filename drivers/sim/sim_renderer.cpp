#include "drivers/sim/sim_renderer.hpp"

#include <cmath>

#include "drivers/sim/sim_trace.hpp"

namespace probeless::sim {

namespace {

struct Bound {
  Eigen::Vector3f centre;  // camera frame
  float radius;
  std::array<float, 4> rect;  // pixels: x0, y0, x1, y1
  bool has_rect;
};

// The cone of a tile (camera frame) meets the sphere seen from the camera centre.
bool cone_meets_sphere(const Eigen::Vector3f& axis, float cos_half, float sin_half,
                       const Eigen::Vector3f& to_centre, float radius) {
  const float dist = to_centre.norm();
  if (dist <= radius) return true;
  const float sin_b = radius / dist, cos_b = std::sqrt(1 - sin_b * sin_b);
  // cos(half + b); when half + b reaches pi everything is inside.
  const float cos_sum = cos_half * cos_b - sin_half * sin_b;
  if (sin_half * cos_b + cos_half * sin_b < 0 && cos_sum < 0) return true;
  return axis.dot(to_centre) >= cos_sum * dist;
}

}  // namespace

SimRenderer::SimRenderer(std::shared_ptr<const SimWorld> world, int width, int height, double fx,
                         double fy, double cx, double cy, WorkerPool* pool)
    : world_(std::move(world)),
      width_(width),
      height_(height),
      fx_(fx),
      fy_(fy),
      cx_(cx),
      cy_(cy),
      pool_(pool) {
  build_tiles();
}

SimRenderer::SimRenderer(std::shared_ptr<const SimWorld> world, const CameraModel& camera,
                         WorkerPool* pool)
    : world_(std::move(world)), width_(camera.width()), height_(camera.height()), pool_(pool) {
  table_.resize(static_cast<std::size_t>(width_) * height_, Eigen::Vector3f::Zero());
  valid_.assign(table_.size(), 0);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const auto ray = camera.unproject(Eigen::Vector2d(x, y));
      if (!ray) continue;
      table_[static_cast<std::size_t>(y) * width_ + x] = ray->cast<float>();
      valid_[static_cast<std::size_t>(y) * width_ + x] = 1;
    }
  }
  build_tiles();
}

void SimRenderer::build_tiles() {
  radiance_ = ImageRGBF(width_, height_);
  for (int y0 = 0; y0 < height_; y0 += kTile) {
    for (int x0 = 0; x0 < width_; x0 += kTile) {
      Tile t{x0, y0, std::min(x0 + kTile, width_), std::min(y0 + kTile, height_), {}, 1, 0, false};
      std::vector<Eigen::Vector3f> rays;
      for (int y = t.y0; y < t.y1; ++y) {
        for (int x = t.x0; x < t.x1; ++x) {
          if (table_.empty()) {
            rays.push_back(Eigen::Vector3f((x - cx_) / fx_, (y - cy_) / fy_, 1).normalized());
          } else if (valid_[static_cast<std::size_t>(y) * width_ + x]) {
            rays.push_back(table_[static_cast<std::size_t>(y) * width_ + x]);
          }
        }
      }
      t.any_valid = !rays.empty();
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      for (const auto& r : rays) sum += r;
      t.axis = sum.norm() > 1e-6f ? Eigen::Vector3f(sum.normalized()) : Eigen::Vector3f::UnitZ();
      float min_cos = 1;
      for (const auto& r : rays) min_cos = std::min(min_cos, t.axis.dot(r));
      const float half = std::acos(std::clamp(min_cos, -1.0f, 1.0f)) + 1e-3f;
      t.cos_half = std::cos(half);
      t.sin_half = std::sin(half);
      tiles_.push_back(t);
    }
  }
  lists_.resize(tiles_.size());
  had_dynamic_.assign(tiles_.size(), 0);
}

void SimRenderer::render(const Pose& T_world_camera, int lamp_state, const Occluder* occluder,
                         bool with_depth) {
  if (with_depth && depth_.empty()) {
    depth_ = ImageF(width_, height_);
    flags_ = ImageGray8(width_, height_);
  }
  const Eigen::Matrix3f rotation = T_world_camera.rotation.toRotationMatrix().cast<float>();
  const Eigen::Vector3f origin = T_world_camera.translation.cast<float>();
  const bool same_view = have_last_ && lamp_state == last_lamp_state_ &&
                         with_depth == last_with_depth_ &&
                         T_world_camera.translation == last_pose_.translation &&
                         T_world_camera.rotation.coeffs() == last_pose_.rotation.coeffs();

  // Per primitive, a bound to cull tiles with: for the pinhole the screen rectangle of its
  // bounding box's corners (tight for the thin table top and long sofa, and conservative as
  // long as every corner is in front), else a sphere against the tile's cone of rays.
  const SimWorld& w = *world_;
  const Eigen::Matrix3f to_camera = rotation.transpose();
  std::vector<std::pair<PrimRef, Bound>> bounds;
  const auto add = [&](PrimRef ref, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                       const Eigen::Vector3f& centre, float radius) {
    Bound b{to_camera * (centre - origin), radius, {}, false};
    if (table_.empty()) {
      float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
      bool in_front = true;
      for (int c = 0; c < 8 && in_front; ++c) {
        const Eigen::Vector3f corner((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                                     (c & 4) ? hi.z() : lo.z());
        const Eigen::Vector3f q = to_camera * (corner - origin);
        in_front = q.z() > 1e-3f;
        const float u = static_cast<float>(fx_) * q.x() / q.z() + static_cast<float>(cx_);
        const float v = static_cast<float>(fy_) * q.y() / q.z() + static_cast<float>(cy_);
        x0 = std::min(x0, u);
        x1 = std::max(x1, u);
        y0 = std::min(y0, v);
        y1 = std::max(y1, v);
      }
      b.has_rect = in_front;
      b.rect = {x0 - 1, y0 - 1, x1 + 1, y1 + 1};
    }
    bounds.push_back({ref, b});
  };
  for (const PrimRef& p : w.static_prims()) {
    if (p.kind == PrimRef::Kind::Box) {
      const Box& box = w.boxes()[p.index];
      add(p, box.lo, box.hi, 0.5f * (box.lo + box.hi), 0.5f * (box.hi - box.lo).norm());
    } else {
      const Sphere& s = w.spheres()[p.index];
      const Eigen::Vector3f r = Eigen::Vector3f::Constant(s.radius);
      add(p, s.centre - r, s.centre + r, s.centre, s.radius);
    }
  }
  const std::size_t n_static = bounds.size();
  if (occluder) {
    for (std::size_t i = 0; i < occluder->capsules.size(); ++i) {
      const Capsule& c = occluder->capsules[i];
      const Eigen::Vector3f r = Eigen::Vector3f::Constant(c.radius);
      add({PrimRef::Kind::Capsule, static_cast<std::uint8_t>(i)}, c.a.cwiseMin(c.b) - r,
          c.a.cwiseMax(c.b) + r, 0.5f * (c.a + c.b), 0.5f * (c.b - c.a).norm() + c.radius);
    }
    for (std::size_t j = 0; j < occluder->boxes.size(); ++j) {
      const MovingBox& b = occluder->boxes[j];
      add({PrimRef::Kind::OccluderBox, static_cast<std::uint8_t>(j)}, b.lo, b.hi,
          0.5f * (b.lo + b.hi), 0.5f * (b.hi - b.lo).norm());
    }
  }

  std::vector<int> to_cast;
  for (std::size_t ti = 0; ti < tiles_.size(); ++ti) {
    const Tile& t = tiles_[ti];
    TileList& list = lists_[ti];
    list.count = 0;
    list.dynamic = false;
    if (!t.any_valid) continue;
    for (std::size_t bi = 0; bi < bounds.size() && list.count < kMaxPrims; ++bi) {
      const Bound& b = bounds[bi].second;
      const bool meets =
          b.has_rect ? b.rect[0] <= t.x1 - 1 && b.rect[2] >= t.x0 && b.rect[1] <= t.y1 - 1 &&
                           b.rect[3] >= t.y0
                     : cone_meets_sphere(t.axis, t.cos_half, t.sin_half, b.centre, b.radius);
      if (!meets) continue;
      list.prims[list.count++] = bounds[bi].first;
      list.dynamic |= bi >= n_static;
    }
    if (!same_view || list.dynamic || had_dynamic_[ti]) to_cast.push_back(static_cast<int>(ti));
    had_dynamic_[ti] = list.dynamic;
  }

  const auto cast = [&](int k) {
    cast_tile(to_cast[k], rotation, origin, lamp_state, occluder, with_depth);
  };
  if (pool_) {
    pool_->parallel_for(static_cast<int>(to_cast.size()), cast);
  } else {
    for (int k = 0; k < static_cast<int>(to_cast.size()); ++k) cast(k);
  }
  tiles_cast_ = static_cast<int>(to_cast.size());
  edge_pixels_.clear();
  if (edge_samples_ > 1 && with_depth && table_.empty())
    supersample_edges(rotation, origin, lamp_state, occluder);
  have_last_ = true;
  last_pose_ = T_world_camera;
  last_lamp_state_ = lamp_state;
  last_with_depth_ = with_depth;
}

void SimRenderer::cast_tile(int index, const Eigen::Matrix3f& rotation,
                            const Eigen::Vector3f& origin, int lamp_state, const Occluder* occluder,
                            bool with_depth) {
  const Tile& t = tiles_[index];
  const TileList& list = lists_[index];
  const std::span<const PrimRef> prims(list.prims.data(), list.count);
  const SimWorld& w = *world_;
  const float inv_fx = static_cast<float>(1.0 / (fx_ == 0 ? 1 : fx_));
  const float inv_fy = static_cast<float>(1.0 / (fy_ == 0 ? 1 : fy_));
  for (int y = t.y0; y < t.y1; ++y) {
    float* rad = radiance_.row(y);
    for (int x = t.x0; x < t.x1; ++x) {
      Eigen::Vector3f d;
      if (table_.empty()) {
        const float xn = (x - static_cast<float>(cx_)) * inv_fx;
        const float yn = (y - static_cast<float>(cy_)) * inv_fy;
        d = rotation.col(0) * xn + rotation.col(1) * yn + rotation.col(2);
      } else {
        const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
        if (!valid_[i]) {
          rad[3 * x] = rad[3 * x + 1] = rad[3 * x + 2] = 0;
          continue;
        }
        d = rotation * table_[i];
      }
      const Ray ray(origin, d);
      const Hit hit = trace(ray, w, prims, occluder);
      bool has_depth = true;
      if (hit.kind == Hit::Kind::Patch) {
        // The common case, inline: a baked texel of the room or a box.
        const Patch& patch = w.patches()[hit.index];
        const Eigen::Vector3f p = ray.o + hit.t * ray.d;
        const Eigen::Array4f c = patch_texel(patch, lamp_state, p);
        rad[3 * x] = c[0];
        rad[3 * x + 1] = c[1];
        rad[3 * x + 2] = c[2];
        has_depth = !with_depth || patch_has_depth(patch, p);
      } else {
        const Eigen::Vector3f c = shade(ray, hit, w, lamp_state, occluder);
        rad[3 * x] = c.x();
        rad[3 * x + 1] = c.y();
        rad[3 * x + 2] = c.z();
        has_depth = hit.kind != Hit::Kind::Mirror;
      }
      if (with_depth) {
        depth_.at(x, y) = hit.t;
        flags_.at(x, y) = static_cast<std::uint8_t>(
            (hit.kind == Hit::Kind::Occluder ? kFlagOccluder : 0) | (has_depth ? 0 : kFlagNoDepth));
      }
    }
  }
}

}  // namespace probeless::sim
