#pragma once
// A bounding volume hierarchy over a triangle mesh for the PRT bake's visibility rays
// (docs/prt.md "Visibility"): binned surface-area-heuristic build, iterative traversal, Moller
// & Trumbore's ray-triangle test. Built once per bake, then read by every bake thread (all
// queries are const). Small meshes of thousands of triangles are the target; docs/prt.md says
// why this is not Embree.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace probeless::prt {

struct Ray {
  Eigen::Vector3f origin;
  Eigen::Vector3f direction;  // need not be unit; t is in its units
  float t_max = std::numeric_limits<float>::infinity();
};

struct RayHit {
  float t = 0;
  std::uint32_t triangle = 0;  // index into the mesh's triangles (indices / 3)
  float u = 0, v = 0;          // barycentric weights of the triangle's second and third corner
};

class TriangleBvh {
 public:
  // Copies the triangles; `indices` are triangles (three per), each below positions.size().
  TriangleBvh(const std::vector<Eigen::Vector3f>& positions,
              const std::vector<std::uint32_t>& indices);

  // Whether anything lies on the ray for 0 < t < t_max (shadow rays: the first hit ends it).
  bool occluded(const Ray& ray) const;
  // The nearest hit with 0 < t < t_max, front or back face alike.
  std::optional<RayHit> closest(const Ray& ray) const;

  std::size_t node_count() const { return nodes_.size(); }
  std::size_t triangle_count() const { return triangles_.size(); }

 private:
  struct Node {
    Eigen::Vector3f lo, hi;
    // Leaf (count > 0): triangles first .. first + count - 1. Inner: the left child follows
    // this node, the right child is at `first`.
    std::uint32_t first = 0, count = 0;
  };
  struct Triangle {
    Eigen::Vector3f v0, e1, e2;  // corner and the two edges from it
    std::uint32_t index = 0;     // in the mesh
  };

  template <bool AnyHit>
  bool traverse(const Ray& ray, RayHit* hit) const;
  std::uint32_t build(std::vector<std::uint32_t>& order, const std::vector<Eigen::Vector3f>& lo,
                      const std::vector<Eigen::Vector3f>& hi,
                      const std::vector<Eigen::Vector3f>& centre, std::uint32_t begin,
                      std::uint32_t end, int depth);

  std::vector<Node> nodes_;
  std::vector<Triangle> triangles_;  // in leaf order
};

}  // namespace probeless::prt
