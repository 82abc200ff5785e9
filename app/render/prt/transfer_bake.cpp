#include "app/render/prt/transfer_bake.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>

#include "core/sh.hpp"
#include "core/sphere_sampling.hpp"

namespace probeless::prt {

Occluders::Result Occluders::trace(const Eigen::Vector3f& start,
                                   const Eigen::Vector3f& start_direction) const {
  Eigen::Vector3f origin = start, direction = start_direction;
  float weight = 1.f;
  for (int bounce = 0;; ++bounce) {
    float plane_t = std::numeric_limits<float>::infinity();
    if (plane) {
      const Eigen::Vector3f n = plane->head<3>();
      const float height = n.dot(origin) + plane->w(), along = n.dot(direction);
      if (height < 0.f) return {};  // starts inside the table: a face resting on it
      if (along < 0.f) plane_t = -height / along;
    }
    const bool hits_plane = plane_t < std::numeric_limits<float>::infinity();
    const Result escaped{weight, bounce > 0, direction};
    if (!object) return hits_plane ? Result{} : escaped;
    if (!mirror && !triangle_reflectance) {
      // Shadow rays only need to know whether anything is in the way, not what.
      if (hits_plane || object->occluded({origin, direction})) return {};
      return escaped;
    }
    const auto hit = object->closest({origin, direction, plane_t});
    if (!hit) return hits_plane ? Result{} : escaped;
    if (bounce == max_bounces) return {};
    const float r = triangle_reflectance ? (*triangle_reflectance)[hit->triangle] : reflectance;
    if (!(r > 0.f)) return {};  // a diffuse triangle (or a black mirror) blocks

    // Thesis ch. 6: a mirror-like object reflects the shadow ray on into the scene. Reflect
    // about the interpolated normal (smooth, like the rendered mirror) and leave from the side
    // of the geometric face the ray arrived on.
    const auto& ix = object_mesh->indices;
    const auto& p = object_mesh->positions;
    const auto& nn = object_mesh->normals;
    const std::uint32_t a = ix[3 * hit->triangle], b = ix[3 * hit->triangle + 1],
                        c = ix[3 * hit->triangle + 2];
    Eigen::Vector3f geometric = (p[b] - p[a]).cross(p[c] - p[a]).normalized();
    if (geometric.dot(direction) > 0.f) geometric = -geometric;
    Eigen::Vector3f shading =
        ((1.f - hit->u - hit->v) * nn[a] + hit->u * nn[b] + hit->v * nn[c]).normalized();
    if (shading.dot(geometric) < 0.f) shading = -shading;  // hit from inside: mirror both
    origin += hit->t * direction;
    direction -= 2.f * direction.dot(shading) * shading;
    if (!(direction.dot(geometric) > 0.f)) return {};  // smoothing sent it into the surface
    origin += epsilon * geometric;
    weight *= r;
  }
}

Transfer bake_transfer(const std::vector<Eigen::Vector3f>& positions,
                       const std::vector<Eigen::Vector3f>& normals, const Occluders& occluders,
                       const std::vector<Eigen::Vector3d>& directions, unsigned threads) {
  Transfer out;
  out.coefficients.assign(positions.size() * kTransferCount, 0.f);
  if (positions.empty() || directions.empty()) return out;
  const double inv_n = 1.0 / static_cast<double>(directions.size());

  auto bake_vertex = [&](std::size_t v) {
    const Eigen::Vector3d n = normals[v].cast<double>();
    if (!(n.norm() > 1e-6)) return;  // no hemisphere to integrate over: zero transfer
    const Eigen::Matrix3d frame = orthonormal_basis(n.normalized());
    const Eigen::Vector3f origin = positions[v] + occluders.epsilon * normals[v].normalized();
    std::array<double, kTransferCount> sum{};
    for (const Eigen::Vector3d& local : directions) {
      const Eigen::Vector3d w = frame * local;
      const Occluders::Result r = occluders.trace(origin, w.cast<float>());
      if (r.weight <= 0.f) continue;
      const ShBasis y = sh_basis(r.reflected ? r.direction.cast<double>() : w);
      for (int i = 0; i < kTransferCount; ++i) sum[i] += r.weight * y[i];
    }
    for (int i = 0; i < kTransferCount; ++i)
      out.coefficients[v * kTransferCount + i] = static_cast<float>(sum[i] * inv_n);
  };

  // Chunks from a shared counter rather than fixed ranges: vertices in a concave fold cost
  // more rays through the hierarchy than open ones, and the two cores are shared.
  constexpr std::size_t kChunk = 32;
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    try {
      for (;;) {
        const std::size_t begin = next.fetch_add(kChunk);
        if (begin >= positions.size()) return;
        const std::size_t end = std::min(positions.size(), begin + kChunk);
        for (std::size_t v = begin; v < end; ++v) bake_vertex(v);
      }
    } catch (...) {
      const std::lock_guard lock(error_mutex);
      if (!error) error = std::current_exception();
      next = positions.size();  // the others stop at their next chunk
    }
  };
  {
    std::vector<std::jthread> pool;
    const std::size_t chunks = (positions.size() + kChunk - 1) / kChunk;
    const auto helpers = std::min<std::size_t>(std::max(threads, 1u), chunks) - 1;
    for (std::size_t t = 0; t < helpers; ++t) pool.emplace_back(worker);
    worker();
  }  // joined here
  if (error) std::rethrow_exception(error);
  return out;
}

}  // namespace probeless::prt
