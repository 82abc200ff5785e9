#include "app/render/prt/prt.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "app/render/prt/bvh.hpp"
#include "app/render/prt/prt_cache.hpp"
#include "app/render/prt/transfer_bake.hpp"
#include "core/sphere_sampling.hpp"

namespace probeless::prt {
namespace {

// Rays start this fraction of the object's bounding radius off the surface: far above float
// rounding at the object's size (1e-7 relative), far below any feature that casts a shadow.
constexpr float kRayOffset = 1e-4f;
constexpr int kMaxSamples = 1 << 20;
constexpr int kMaxSubdivisions = 1024;

// The grid's vertices from uniform steps u in [-1, 1]: (u + 2 u^3) / 3 keeps the ends and
// makes the spacing 1/3 of the uniform one at the centre, where the contact shadow changes
// fastest, and 7/3 of it at the edge, where the shadow has faded.
float graded(float u) {
  return (u + 2.f * u * u * u) / 3.f;
}

struct Bounds {
  Eigen::Vector3f centre;
  float radius;
};

Bounds bounding_sphere(const render::Mesh& mesh) {
  const auto [lo, hi] = mesh.bounds();
  return {(lo + hi) / 2, (hi - lo).norm() / 2};
}

void check_mesh(const render::Mesh& mesh) {
  mesh.validate();  // sizes, index range, finite values (std::invalid_argument)
  if (mesh.triangle_count() == 0)
    throw std::invalid_argument(fmt::format("prt: mesh '{}' has no triangles", mesh.name));
  if (!(bounding_sphere(mesh).radius > 0.f))
    throw std::invalid_argument(fmt::format("prt: mesh '{}' has no extent", mesh.name));
}

Eigen::Vector3f check_ground(const Ground& g) {
  const Eigen::Vector3f& n = g.plane.normal;
  if (!n.allFinite() || !(n.norm() > 1e-12f))
    throw std::invalid_argument(
        fmt::format("prt: the ground plane's normal ({}, {}, {}) must be finite and non-zero",
                    n.x(), n.y(), n.z()));
  if (!g.plane.point.allFinite())
    throw std::invalid_argument("prt: the ground plane's point must be finite");
  if (!std::isfinite(g.side_radii) || !(g.side_radii > 0.f))
    throw std::invalid_argument(
        fmt::format("prt: ground side_radii must be positive (got {})", g.side_radii));
  if (g.side && (!std::isfinite(*g.side) || !(*g.side > 0.f)))
    throw std::invalid_argument(fmt::format("prt: ground side must be positive (got {})", *g.side));
  if (g.subdivisions < 1 || g.subdivisions > kMaxSubdivisions)
    throw std::invalid_argument(fmt::format("prt: ground subdivisions must be 1..{} (got {})",
                                            kMaxSubdivisions, g.subdivisions));
  return n.normalized();
}

void check(const render::Mesh& object, const Scene& scene, const BakeOptions& options) {
  check_mesh(object);
  if (options.samples <= 0 || options.samples > kMaxSamples)
    throw std::invalid_argument(
        fmt::format("prt: samples must be 1..{} (got {})", kMaxSamples, options.samples));
  if (options.max_mirror_bounces < 0)
    throw std::invalid_argument("prt: max_mirror_bounces must not be negative");
  if (!(scene.mirror_reflectance >= 0.f && scene.mirror_reflectance <= 1.f))
    throw std::invalid_argument(
        fmt::format("prt: mirror_reflectance must be in 0..1 (got {})", scene.mirror_reflectance));
  if (!scene.triangle_reflectance.empty()) {
    if (scene.triangle_reflectance.size() != object.triangle_count())
      throw std::invalid_argument(
          fmt::format("prt: triangle_reflectance has {} values for {} triangles",
                      scene.triangle_reflectance.size(), object.triangle_count()));
    for (float r : scene.triangle_reflectance)
      if (!(r >= 0.f && r <= 1.f))
        throw std::invalid_argument(
            fmt::format("prt: triangle_reflectance must be in 0..1 (got {})", r));
  }
  if (scene.ground) check_ground(*scene.ground);
}

}  // namespace

Eigen::Vector3d Transfer::radiance(std::size_t vertex, const ShRgb& object_radiance) const {
  const auto t = at(vertex);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = 0; i < std::min(kTransferCount, object_radiance.count()); ++i)
    sum += static_cast<double>(t[i]) * object_radiance.c[i];
  return sum;
}

Transfer Bake::ground_difference() const {
  Transfer d = ground_with_object;
  for (std::size_t k = 0; k < d.coefficients.size(); ++k)
    d.coefficients[k] -= ground_without_object.coefficients[k];
  return d;
}

render::Mesh make_ground_grid(const render::Mesh& object, const Ground& ground) {
  check_mesh(object);
  const Eigen::Vector3f n = check_ground(ground);
  const Bounds b = bounding_sphere(object);
  // Centred where the bounding box's centre drops onto the plane: under the object.
  const Eigen::Vector3f centre = b.centre - (b.centre - ground.plane.point).dot(n) * n;
  const Eigen::Matrix3f frame = orthonormal_basis(n.cast<double>()).cast<float>();
  const float side = ground.side ? *ground.side : ground.side_radii * b.radius;
  const int k = ground.subdivisions;

  render::Mesh grid;
  grid.name = "prt-ground";
  for (int j = 0; j <= k; ++j)
    for (int i = 0; i <= k; ++i) {
      const float s = graded(2.f * static_cast<float>(i) / k - 1.f) * side / 2;
      const float t = graded(2.f * static_cast<float>(j) / k - 1.f) * side / 2;
      grid.positions.push_back(centre + s * frame.col(0) + t * frame.col(1));
      grid.normals.push_back(n);
    }
  // (t, b, n) is right-handed, so (i, j) -> (i + 1, j) -> (i + 1, j + 1) turns
  // counter-clockwise seen from the normal's side, as meshes here do from outside.
  const auto row = static_cast<std::uint32_t>(k + 1);
  for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(k); ++j)
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(k); ++i) {
      const std::uint32_t a = j * row + i, c = a + row;
      grid.indices.insert(grid.indices.end(), {a, a + 1, c + 1, a, c + 1, c});
    }
  return grid;
}

Bake bake_prt(const render::Mesh& object, const Scene& scene, const BakeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check(object, scene, options);
  Bake out;
  if (scene.ground) out.ground = make_ground_grid(object, *scene.ground);
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };

  std::vector<std::size_t> counts{object.vertex_count()};
  if (scene.ground) counts.insert(counts.end(), 2, out.ground.vertex_count());
  const std::string key = bake_cache_key(object, scene, options);
  const TransferCache cache(options.cache_dir);
  if (!options.cache_dir.empty()) {
    auto entry = cache.load(object.name, key, counts);
    if (entry.status == TransferCache::Lookup::Hit) {
      out.object = std::move(entry.blocks[0]);
      if (scene.ground) {
        out.ground_with_object = std::move(entry.blocks[1]);
        out.ground_without_object = std::move(entry.blocks[2]);
      }
      out.cache = CacheOutcome::Hit;
      out.seconds = elapsed();
      spdlog::debug("prt: {} loaded from {}", object.name,
                    cache.path_for(object.name, key).string());
      return out;
    }
    out.cache = CacheOutcome::Missing;
    if (entry.status == TransferCache::Lookup::Corrupt) {
      spdlog::warn("prt: cache file {} is unusable ({}); baking again",
                   cache.path_for(object.name, key).string(), entry.problem);
      cache.remove(object.name, key);
      out.cache = CacheOutcome::Corrupt;
    }
  }

  const unsigned threads =
      options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const TriangleBvh bvh(object.positions, object.indices);
  const auto directions =
      cosine_hemisphere_set(static_cast<std::uint32_t>(options.samples), options.seed);
  Occluders occluders;
  occluders.object = &bvh;
  occluders.object_mesh = &object;
  occluders.mirror = scene.mirror;
  occluders.reflectance = scene.mirror_reflectance;
  if (!scene.triangle_reflectance.empty())
    occluders.triangle_reflectance = &scene.triangle_reflectance;
  occluders.max_bounces = options.max_mirror_bounces;
  occluders.epsilon = kRayOffset * bounding_sphere(object).radius;
  if (scene.ground) {
    const Eigen::Vector3f n = scene.ground->plane.normal.normalized();
    occluders.plane = Eigen::Vector4f(n.x(), n.y(), n.z(), -n.dot(scene.ground->plane.point));
  }
  out.object = bake_transfer(object.positions, object.normals, occluders, directions, threads);
  if (scene.ground) {
    out.ground_with_object =
        bake_transfer(out.ground.positions, out.ground.normals, occluders, directions, threads);
    // The same directions with nothing in the way: where the object blocks no ray the two
    // bakes agree to the bit, so the difference is exactly zero. Nothing is in the way of any
    // vertex and all have the plane's normal, so one vertex's row is every vertex's row.
    Occluders alone = occluders;
    alone.object = nullptr;
    const Transfer row =
        bake_transfer({out.ground.positions[0]}, {out.ground.normals[0]}, alone, directions, 1);
    out.ground_without_object.coefficients.reserve(row.coefficients.size() *
                                                   out.ground.vertex_count());
    for (std::size_t v = 0; v < out.ground.vertex_count(); ++v)
      out.ground_without_object.coefficients.insert(out.ground_without_object.coefficients.end(),
                                                    row.coefficients.begin(),
                                                    row.coefficients.end());
  }

  if (!options.cache_dir.empty()) {
    std::vector<const Transfer*> blocks{&out.object};
    if (scene.ground)
      blocks.insert(blocks.end(), {&out.ground_with_object, &out.ground_without_object});
    out.stored = cache.store(object.name, key, blocks);
    if (!out.stored)
      spdlog::warn("prt: cannot write the bake of {} to {}; it will be baked again next start",
                   object.name, options.cache_dir.string());
  }
  out.seconds = elapsed();
  spdlog::info("prt: baked {} ({} vertices{}, {} samples, {} threads) in {:.2f} s", object.name,
               object.vertex_count(),
               scene.ground ? fmt::format(" + {} ground", out.ground.vertex_count()) : "",
               options.samples, threads, out.seconds);
  return out;
}

}  // namespace probeless::prt
