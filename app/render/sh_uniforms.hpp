#pragma once
// The SH lighting uniforms of the diffuse materials, computed on the CPU per object and
// frame (cheap: a few hundred flops), and kept apart from the GL code so that tests can
// check them against core's SH functions.
#include <Eigen/Core>
#include <array>

#include "core/sh.hpp"

namespace probeless::render {

// Ramamoorthi & Hanrahan 2001, eq. 12: per channel the symmetric 4x4 M with
// E(n) = (n, 1)^T M (n, 1), from the first 9 radiance coefficients (needs >= 3 bands). Equal
// to core's sh_irradiance (eq. 13) for every unit n.
std::array<Eigen::Matrix4f, 3> irradiance_matrices(const ShRgb& radiance);

// The PRT material's light: the world-frame radiance coefficients turned into the object
// frame (R_world_object^T, core's sh_rotation), channel c's coefficient i at [28 c + i],
// zeros in 25..27: 21 vec4 uniforms. Bands missing from `radiance` count as zero.
std::array<float, 84> prt_light(const ShRgb& radiance_world, const Eigen::Matrix3d& R_world_object);

}  // namespace probeless::render
