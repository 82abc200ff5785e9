#pragma once
// Sample directions for Monte Carlo integrals over the hemisphere, as the PRT bake uses them
// (docs/prt.md): a Hammersley point set on the unit square, shifted by a seeded offset, mapped
// to cosine-weighted directions. Pure maths, deterministic, no state.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace probeless {

// Point i of the n-point Hammersley set, ((i + 0.5) / n, radical inverse of i in base 2),
// shifted by `offset` modulo 1 (a Cranley-Patterson rotation). The shift keeps the set's
// stratification, and over uniform offsets the estimate is unbiased (Pharr, Jakob & Humphreys,
// "Physically Based Rendering", 3rd ed., 7.4 and 7.7). Throws std::invalid_argument if i >= n.
Eigen::Vector2d hammersley(std::uint32_t i, std::uint32_t n,
                           const Eigen::Vector2d& offset = Eigen::Vector2d::Zero());

// An offset in [0, 1)^2 from a seed (SplitMix64), for hammersley(): one seed, one point set.
Eigen::Vector2d seeded_offset(std::uint64_t seed);

// Unit direction on the hemisphere around +z with density cos(theta) / pi, from a point of
// the unit square: Shirley & Chiu's concentric map onto the disk ("A Low Distortion Map
// Between Disk and Square", 1997), lifted to the hemisphere (Malley's method). Both maps keep
// areas proportional, so the square's stratification carries over to the directions.
Eigen::Vector3d cosine_hemisphere(const Eigen::Vector2d& u);

// n cosine-weighted directions around +z from the shifted Hammersley set of `seed`.
std::vector<Eigen::Vector3d> cosine_hemisphere_set(std::uint32_t n, std::uint64_t seed);

// A right-handed orthonormal basis with unit `normal` as its third column (t, b, n): Duff et
// al., "Building an Orthonormal Basis, Revisited" (JCGT 2017). It is continuous in the normal
// except where normal.z changes sign, so neighbouring vertices get nearly the same frame.
Eigen::Matrix3d orthonormal_basis(const Eigen::Vector3d& normal);

}  // namespace probeless
