#include "app/render/prt/bvh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace probeless::prt {
namespace {

constexpr std::uint32_t kMaxLeaf = 4;  // a leaf when the SAH finds nothing better
constexpr int kBins = 12;              // binned SAH (Wald 2007): 8-16 bins lose little
constexpr int kMaxDepth = 60;          // under the traversal stack's 64 entries
constexpr float kTraversalCost = 1.f;  // relative to one triangle test

float half_area(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  const Eigen::Vector3f d = (hi - lo).cwiseMax(0.f);
  return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
}

struct Box {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(-std::numeric_limits<float>::infinity());
  void grow(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
    lo = lo.cwiseMin(a);
    hi = hi.cwiseMax(b);
  }
};

// Slab test (Kay & Kajiya 1986): entry distance of the ray into the box, or +inf when it
// misses within t_max. Written out per axis: it is most of the bake's time, and the Eigen
// expression with reductions did not inline.
inline float box_entry(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                       const Eigen::Vector3f& o, const Eigen::Vector3f& inv, float t_max) {
  const float x0 = (lo.x() - o.x()) * inv.x(), x1 = (hi.x() - o.x()) * inv.x();
  const float y0 = (lo.y() - o.y()) * inv.y(), y1 = (hi.y() - o.y()) * inv.y();
  const float z0 = (lo.z() - o.z()) * inv.z(), z1 = (hi.z() - o.z()) * inv.z();
  const float t_near =
      std::max(std::max(std::min(x0, x1), std::min(y0, y1)), std::max(std::min(z0, z1), 0.f));
  const float t_far =
      std::min(std::min(std::max(x0, x1), std::max(y0, y1)), std::min(std::max(z0, z1), t_max));
  return t_near <= t_far ? t_near : std::numeric_limits<float>::infinity();
}

}  // namespace

TriangleBvh::TriangleBvh(const std::vector<Eigen::Vector3f>& positions,
                         const std::vector<std::uint32_t>& indices) {
  const auto n = static_cast<std::uint32_t>(indices.size() / 3);
  std::vector<Eigen::Vector3f> lo(n), hi(n), centre(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k)
      if (indices[3 * t + k] >= positions.size())
        throw std::invalid_argument("TriangleBvh: index out of range");
    const Eigen::Vector3f &a = positions[indices[3 * t]], &b = positions[indices[3 * t + 1]],
                          &c = positions[indices[3 * t + 2]];
    lo[t] = a.cwiseMin(b).cwiseMin(c);
    hi[t] = a.cwiseMax(b).cwiseMax(c);
    centre[t] = (lo[t] + hi[t]) / 2;
  }
  if (n == 0) return;
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  nodes_.reserve(2 * static_cast<std::size_t>(n));
  build(order, lo, hi, centre, 0, n, 0);
  triangles_.reserve(n);
  for (std::uint32_t t : order) {
    const Eigen::Vector3f& a = positions[indices[3 * t]];
    triangles_.push_back(
        {a, positions[indices[3 * t + 1]] - a, positions[indices[3 * t + 2]] - a, t});
  }
}

std::uint32_t TriangleBvh::build(std::vector<std::uint32_t>& order,
                                 const std::vector<Eigen::Vector3f>& lo,
                                 const std::vector<Eigen::Vector3f>& hi,
                                 const std::vector<Eigen::Vector3f>& centre, std::uint32_t begin,
                                 std::uint32_t end, int depth) {
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Box box, centres;
  for (std::uint32_t k = begin; k < end; ++k) {
    box.grow(lo[order[k]], hi[order[k]]);
    centres.grow(centre[order[k]], centre[order[k]]);
  }
  const std::uint32_t count = end - begin;
  auto make_leaf = [&] {
    nodes_[index] = {box.lo, box.hi, begin, count};
    return index;
  };
  Eigen::Index axis = 0;
  const float extent = (centres.hi - centres.lo).maxCoeff(&axis);
  if (count <= 1 || extent <= 0.f || depth >= kMaxDepth) return make_leaf();

  // Bin the centroids along the widest axis and sweep the kBins - 1 planes between bins for
  // the least surface-area cost (the chance a ray meets a child is its area over the parent's).
  auto bin_of = [&](std::uint32_t t) {
    const float f = (centre[t][axis] - centres.lo[axis]) / extent;
    return std::min(kBins - 1, static_cast<int>(f * kBins));
  };
  std::array<Box, kBins> bins;
  std::array<std::uint32_t, kBins> counts{};
  for (std::uint32_t k = begin; k < end; ++k) {
    const int b = bin_of(order[k]);
    bins[b].grow(lo[order[k]], hi[order[k]]);
    ++counts[b];
  }
  std::array<float, kBins> right_cost{};
  Box right;
  std::uint32_t n_right = 0;
  for (int b = kBins - 1; b > 0; --b) {
    right.grow(bins[b].lo, bins[b].hi);
    n_right += counts[b];
    right_cost[b] = n_right ? half_area(right.lo, right.hi) * n_right : 0.f;
  }
  Box left;
  std::uint32_t n_left = 0;
  int best_split = -1;
  float best_cost = std::numeric_limits<float>::infinity();
  for (int b = 1; b < kBins; ++b) {
    left.grow(bins[b - 1].lo, bins[b - 1].hi);
    n_left += counts[b - 1];
    if (n_left == 0 || n_left == count) continue;
    const float cost = half_area(left.lo, left.hi) * n_left + right_cost[b];
    if (cost < best_cost) {
      best_cost = cost;
      best_split = b;
    }
  }
  const float split_cost = kTraversalCost + best_cost / std::max(half_area(box.lo, box.hi), 1e-30f);
  if (best_split < 0 || (count <= kMaxLeaf && split_cost >= static_cast<float>(count)))
    return make_leaf();

  const auto mid_it = std::partition(order.begin() + begin, order.begin() + end,
                                     [&](std::uint32_t t) { return bin_of(t) < best_split; });
  const auto mid = static_cast<std::uint32_t>(mid_it - order.begin());
  build(order, lo, hi, centre, begin, mid, depth + 1);  // at index + 1
  const std::uint32_t right_child = build(order, lo, hi, centre, mid, end, depth + 1);
  nodes_[index] = {box.lo, box.hi, right_child, 0};
  return index;
}

template <bool AnyHit>
bool TriangleBvh::traverse(const Ray& ray, RayHit* hit) const {
  if (nodes_.empty()) return false;
  // A zero direction component would make 0 * inf = NaN in the slab test; a tiny one only
  // makes that slab infinitely wide, which is right.
  Eigen::Vector3f inv;
  for (int k = 0; k < 3; ++k) {
    const float d = ray.direction[k];
    inv[k] = 1.f / (std::abs(d) > 1e-20f ? d : std::copysign(1e-20f, d));
  }
  const Eigen::Vector3f& o = ray.origin;
  float t_max = ray.t_max;
  bool found = false;
  std::array<std::uint32_t, 64> stack;
  int top = 0;
  if (box_entry(nodes_[0].lo, nodes_[0].hi, o, inv, t_max) ==
      std::numeric_limits<float>::infinity())
    return false;
  std::uint32_t node = 0;
  for (;;) {
    const Node& nd = nodes_[node];
    if (nd.count > 0) {
      // Moller & Trumbore 1997: Cramer's rule on o + t d = v0 + u e1 + v e2.
      for (std::uint32_t k = nd.first; k < nd.first + nd.count; ++k) {
        const Triangle& tri = triangles_[k];
        const Eigen::Vector3f p = ray.direction.cross(tri.e2);
        const float det = tri.e1.dot(p);
        if (std::abs(det) < 1e-30f) continue;  // ray parallel to the triangle
        const float inv_det = 1.f / det;
        const Eigen::Vector3f s = o - tri.v0;
        const float u = s.dot(p) * inv_det;
        if (u < 0.f || u > 1.f) continue;
        const Eigen::Vector3f q = s.cross(tri.e1);
        const float v = ray.direction.dot(q) * inv_det;
        if (v < 0.f || u + v > 1.f) continue;
        const float t = tri.e2.dot(q) * inv_det;
        if (t <= 0.f || t >= t_max) continue;
        if constexpr (AnyHit) return true;
        t_max = t;
        *hit = {t, tri.index, u, v};
        found = true;
      }
    } else {
      // Visit the nearer child first and keep the other for later: with closest hits this
      // shrinks t_max early, so more of the far subtree is skipped.
      std::uint32_t a = node + 1, b = nd.first;
      float ta = box_entry(nodes_[a].lo, nodes_[a].hi, o, inv, t_max);
      float tb = box_entry(nodes_[b].lo, nodes_[b].hi, o, inv, t_max);
      if (tb < ta) {
        std::swap(a, b);
        std::swap(ta, tb);
      }
      if (ta != std::numeric_limits<float>::infinity()) {
        if (tb != std::numeric_limits<float>::infinity()) stack[top++] = b;
        node = a;
        continue;
      }
    }
    // Pop; a node pushed before t_max shrank may now be out of reach, which its own box test
    // on the next level (or the triangle tests) rejects.
    if (top == 0) break;
    node = stack[--top];
  }
  return found;
}

bool TriangleBvh::occluded(const Ray& ray) const {
  return traverse<true>(ray, nullptr);
}

std::optional<RayHit> TriangleBvh::closest(const Ray& ray) const {
  RayHit hit;
  if (!traverse<false>(ray, &hit)) return std::nullopt;
  return hit;
}

}  // namespace probeless::prt
