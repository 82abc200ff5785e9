#pragma once
// Precomputed radiance transfer (PRT) for shadowed diffuse surfaces, baked on the CPU at model
// load (issue #6, thesis ch. 6; Sloan, Kautz & Snyder 2002, "Precomputed Radiance Transfer";
// docs/prt.md has the derivation, the parameters and the measurements).
//
// THE CONTRACT (what a shader reads):
//   Transfer::coefficients[vertex * 25 + i], float, i = l (l + 1) + m over 5 bands, in the
//   real SH basis of core/sh.hpp (R&H signs, no Condon-Shortley phase), directions in the
//   OBJECT frame of the mesh that was baked:
//     T_i(x) = 1/pi * integral over the sphere of V(x, w) max(0, n(x) . w) y_i(w) dw
//   and a Lambertian vertex of albedo rho leaves radiance
//     rho * sum_i T_i L_i
//   where L_i are the environment's radiance coefficients (project_sh) in the same object
//   frame: rotate_sh(L_world, R_object_world). An unoccluded vertex under constant radiance c
//   has T_0 = 1 / (2 sqrt(pi)) and L_0 = 2 sqrt(pi) c, so it leaves rho * c.
//   V is 1 when the ray from x towards w escapes the scene, 0 when the object or the ground
//   plane blocks it, and reflectance^k y_i(w') in place of y_i(w) when k mirror bounces off a
//   mirror object send it out along w' (thesis ch. 6: mirrors' shadows are not too dark).
//
// Differential rendering (Debevec 1998) uses the ground's two transfers: the real pixel of the
// plane gains rho_real * sum_i (T_with - T_without)_i L_i (the contact shadow, negative), or
// is scaled by sum T_with L / sum T_without L when the real albedo is not known.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "app/render/mesh.hpp"
#include "core/sh.hpp"

namespace probeless::prt {

inline constexpr int kTransferBands = 5;
inline constexpr int kTransferCount = kTransferBands * kTransferBands;  // 25 per vertex
// Bumped whenever the same inputs would bake to different numbers; part of the cache key.
inline constexpr std::uint32_t kBakeVersion = 1;

struct Transfer {
  std::vector<float> coefficients;  // vertex * kTransferCount + i

  std::size_t vertex_count() const { return coefficients.size() / kTransferCount; }
  std::span<const float, kTransferCount> at(std::size_t vertex) const {
    return std::span<const float, kTransferCount>(coefficients.data() + vertex * kTransferCount,
                                                  kTransferCount);
  }
  // sum_i T_i L_i: the radiance the vertex leaves per unit albedo (RGB), L in the object frame.
  Eigen::Vector3d radiance(std::size_t vertex, const ShRgb& object_radiance) const;
  bool operator==(const Transfer&) const = default;
};

// A real plane in the object frame: the side the normal points to is free space, the other is
// solid (a table top), so it blocks every ray that goes down through it or starts below it.
struct Plane {
  Eigen::Vector3f point = Eigen::Vector3f::Zero();
  Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();  // any length > 0
};

// The receiver grid for differential rendering: a square on the plane centred under the
// object's bounding box, `side_radii` times the bounding sphere's radius (half the box's
// diagonal) on a side, `subdivisions` quads per side, graded: the spacing at the centre is a
// third of the uniform one and at the edge 7/3 of it (the contact shadow changes fastest near
// the object). An even count puts a vertex exactly under the centre.
struct Ground {
  Plane plane{};
  float side_radii = 8.f;
  // When set, the side in object-frame units instead (a world size divided by the object's
  // scale, e.g. the config's [ground] size_m).
  std::optional<float> side{};
  int subdivisions = 64;
};

struct Scene {
  // The object reflects shadow rays (a metal or mirror material) with this reflectance
  // instead of blocking them.
  bool mirror = false;
  float mirror_reflectance = 1.f;  // 0..1
  // Per object triangle (indices / 3), when not empty: its reflectance 0..1 in place of the two
  // above, 0 blocking the ray (a diffuse surface). The service bakes all objects' shadow on the
  // ground in one mesh, where a chrome sphere beside a diffuse pawn reflects and the pawn does
  // not (app/pipeline/scene_objects.cpp).
  std::vector<float> triangle_reflectance{};
  // Without a ground only the object shadows itself and no grid is baked.
  std::optional<Ground> ground{};
};

struct BakeOptions {
  // Cosine-weighted directions per vertex (a shifted Hammersley set, the same for every vertex
  // in its own tangent frame so the error varies smoothly over the surface). 1024 keeps the
  // RMS error of T below 0.5 % of the unoccluded T_0 (docs/prt.md "Sample count").
  int samples = 1024;
  std::uint64_t seed = 1;
  int max_mirror_bounces = 4;  // a ray still on a mirror after this many counts as blocked
  unsigned threads = 0;        // 0: std::thread::hardware_concurrency()
  // Where bakes are kept (the service passes <CacheDirectory>/prt); empty: no disk cache.
  std::filesystem::path cache_dir{};
};

enum class CacheOutcome {
  Off,      // no cache_dir
  Hit,      // loaded, nothing baked
  Missing,  // baked (and stored when the directory is writable)
  Corrupt,  // a file was there but unusable (logged, removed); baked and stored again
};

struct Bake {
  Transfer object;                 // one per object vertex; the ground plane occludes
  render::Mesh ground;             // the receiver grid (object frame); empty without a ground
  Transfer ground_with_object;     // the grid with the object present
  Transfer ground_without_object;  // the grid alone: the clamped cosine, baked the same way
  CacheOutcome cache = CacheOutcome::Off;
  bool stored = false;  // written to the cache by this call
  double seconds = 0;   // wall time of this call (bake or load)

  bool from_cache() const { return cache == CacheOutcome::Hit; }
  // ground_with_object - ground_without_object: what differential rendering adds.
  Transfer ground_difference() const;
};

// Bakes (or loads from options.cache_dir) the object's transfer and, with a ground, the
// grid's. Results do not depend on the thread count. Throws std::invalid_argument naming the
// problem for an empty or invalid mesh, samples <= 0, a zero or non-finite plane normal, a
// reflectance outside 0..1 or bad grid sizes. Vertices with a zero normal get zero transfer.
Bake bake_prt(const render::Mesh& object, const Scene& scene, const BakeOptions& options = {});

// The grid bake_prt bakes for `ground` (validated the same way).
render::Mesh make_ground_grid(const render::Mesh& object, const Ground& ground);

}  // namespace probeless::prt
