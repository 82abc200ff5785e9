#pragma once
// The room while it is being built: how each patch looks (albedo, emission), kept for the
// lighting bake (sim_lighting.cpp) and then dropped. Internal to drivers/sim.
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "drivers/sim/sim_world.hpp"

namespace probeless::sim {

using AlbedoFn = std::function<Eigen::Vector3f(const Eigen::Vector3f&)>;
using EmissionFn = std::function<Eigen::Vector3f(const Eigen::Vector3f&, int lamp_state)>;

// How a patch looks, used while baking and then dropped.
struct PatchSpec {
  AlbedoFn albedo;
  EmissionFn emission;  // may be empty
  float light_spacing;  // lighting is baked on a grid this coarse, then interpolated
};

class WorldBuilder {
 public:
  WorldBuilder(std::uint64_t seed, std::vector<Patch>& patches) : seed_(seed), patches_(patches) {}

  // A face of the axis-aligned box [lo, hi] on `side` (0 low, 1 high) of `axis`, facing out of
  // the box (or into it, for the room).
  int add_face(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int axis, int side,
               bool inward, float texel, float light_spacing, AlbedoFn albedo,
               EmissionFn emission = {}) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const bool positive = (side == 1) != inward;
    Patch p;
    p.normal = Eigen::Vector3f::Unit(axis) * (positive ? 1.0f : -1.0f);
    const int au = positive ? a1 : a2, av = positive ? a2 : a1;
    p.u = Eigen::Vector3f::Unit(au);
    p.v = Eigen::Vector3f::Unit(av);
    p.origin = lo;
    p.origin[axis] = side ? hi[axis] : lo[axis];
    p.size_u = hi[au] - lo[au];
    p.size_v = hi[av] - lo[av];
    p.texel = texel;
    p.nu = std::max(2, static_cast<int>(std::ceil(p.size_u / texel)));
    p.nv = std::max(2, static_cast<int>(std::ceil(p.size_v / texel)));
    p.axis_u = au;
    p.axis_v = av;
    p.scale_u = p.u[au] / texel;
    p.scale_v = p.v[av] / texel;
    p.offset_u = -p.origin[au] * p.scale_u - 0.5f;
    p.offset_v = -p.origin[av] * p.scale_v - 0.5f;
    p.max_fu = static_cast<float>(p.nu) - 1.001f;
    p.max_fv = static_cast<float>(p.nv) - 1.001f;
    patches_.push_back(std::move(p));
    specs_.push_back({std::move(albedo), std::move(emission), light_spacing});
    return static_cast<int>(patches_.size()) - 1;
  }

  // A box with the faces in `faces` (bit axis * 2 + side) visible.
  Box add_box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, unsigned faces, float texel,
              float light_spacing, const AlbedoFn& albedo) {
    Box b{lo, hi, {}};
    for (int f = 0; f < 6; ++f)
      b.patch[f] = (faces >> f) & 1u
                       ? add_face(lo, hi, f / 2, f % 2, false, texel, light_spacing, albedo)
                       : -1;
    return b;
  }

  const std::vector<PatchSpec>& specs() const { return specs_; }
  std::uint64_t seed() const { return seed_; }

 private:
  std::uint64_t seed_;
  std::vector<Patch>& patches_;
  std::vector<PatchSpec> specs_;
};

}  // namespace probeless::sim
