// The hierarchy must find exactly what testing every triangle finds.
#include "app/render/prt/bvh.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "app/render/mesh.hpp"

namespace probeless::prt {
namespace {

// Every triangle in turn, in double precision: the nearest t in (0, t_max), or -1.
double brute_force(const std::vector<Eigen::Vector3f>& p, const std::vector<std::uint32_t>& ix,
                   const Ray& ray, std::uint32_t* triangle) {
  double best = -1;
  const Eigen::Vector3d o = ray.origin.cast<double>(), d = ray.direction.cast<double>();
  for (std::uint32_t t = 0; t < ix.size() / 3; ++t) {
    const Eigen::Vector3d a = p[ix[3 * t]].cast<double>(), b = p[ix[3 * t + 1]].cast<double>(),
                          c = p[ix[3 * t + 2]].cast<double>();
    Eigen::Matrix3d m;
    m << b - a, c - a, -d;
    if (std::abs(m.determinant()) < 1e-15) continue;  // parallel
    const Eigen::Vector3d x = m.inverse() * (o - a);  // u, v, t
    if (x[0] >= 0 && x[1] >= 0 && x[0] + x[1] <= 1 && x[2] > 0 && x[2] < ray.t_max &&
        (best < 0 || x[2] < best)) {
      best = x[2];
      *triangle = t;
    }
  }
  return best;
}

TEST(TriangleBvh, AgreesWithTestingEveryTriangle) {
  // A triangle soup (overlapping, every orientation) and a real mesh.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<Eigen::Vector3f> soup;
  std::vector<std::uint32_t> soup_ix;
  for (std::uint32_t t = 0; t < 300; ++t) {
    const Eigen::Vector3f c(u(rng), u(rng), u(rng));
    for (int k = 0; k < 3; ++k) {
      soup.push_back(c + 0.2f * Eigen::Vector3f(u(rng), u(rng), u(rng)));
      soup_ix.push_back(3 * t + static_cast<std::uint32_t>(k));
    }
  }
  const render::Mesh pawn = render::make_pawn(1.f, 24);
  for (const auto& [p, ix] : {std::pair{soup, soup_ix}, std::pair{pawn.positions, pawn.indices}}) {
    const TriangleBvh bvh(p, ix);
    EXPECT_GT(bvh.node_count(), 1u);
    int hits = 0, misses = 0;
    for (int r = 0; r < 3000; ++r) {
      // From around the shape towards a point near it, so that about half the rays hit.
      const Eigen::Vector3f from = 1.5f * Eigen::Vector3f(u(rng), u(rng), u(rng) + 0.5f);
      const Eigen::Vector3f to = 0.4f * Eigen::Vector3f(u(rng), u(rng), u(rng) + 1.f);
      Ray ray{from, (to - from).normalized()};
      if (r % 3 == 0) ray.t_max = 0.7f;
      std::uint32_t expected_triangle = 0;
      const double expected = brute_force(p, ix, ray, &expected_triangle);
      const auto hit = bvh.closest(ray);
      EXPECT_EQ(bvh.occluded(ray), expected > 0) << "ray " << r;
      ASSERT_EQ(hit.has_value(), expected > 0) << "ray " << r;
      if (!hit) {
        ++misses;
        continue;
      }
      ++hits;
      EXPECT_NEAR(hit->t, expected, 1e-4) << "ray " << r;
      // Equal t can come from two triangles sharing an edge; otherwise the same triangle.
      if (std::abs(hit->t - expected) > 1e-5) continue;
      const Eigen::Vector3f a = p[ix[3 * hit->triangle]], b = p[ix[3 * hit->triangle + 1]],
                            c = p[ix[3 * hit->triangle + 2]];
      const Eigen::Vector3f at = (1 - hit->u - hit->v) * a + hit->u * b + hit->v * c;
      EXPECT_LT((at - (ray.origin + hit->t * ray.direction)).norm(), 1e-4f) << "ray " << r;
    }
    EXPECT_GT(hits, 300);
    EXPECT_GT(misses, 300);
  }
}

TEST(TriangleBvh, AxisAlignedRaysAndEmptyMeshes) {
  const render::Mesh box = render::make_box(Eigen::Vector3f(2, 2, 2));
  const TriangleBvh bvh(box.positions, box.indices);
  // Direction components of exactly zero must not turn the slab test into NaN.
  const auto hit = bvh.closest({Eigen::Vector3f(0.3f, 0.2f, 5), Eigen::Vector3f(0, 0, -1)});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 4.f, 1e-6f);
  EXPECT_FALSE(bvh.occluded({Eigen::Vector3f(0, 0, 5), Eigen::Vector3f(0, 0, 1)}));
  EXPECT_FALSE(bvh.occluded({Eigen::Vector3f(0, 0, 5), Eigen::Vector3f(0, 0, -1), 3.5f}));
  const TriangleBvh empty({}, {});
  EXPECT_FALSE(empty.occluded({Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitX()}));
  EXPECT_THROW(TriangleBvh({Eigen::Vector3f::Zero()}, {0, 0, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::prt
