#pragma once
// The second factor of Karis's split-sum approximation ("Real Shading in Unreal Engine 4",
// SIGGRAPH 2013 course notes, p. 6-7): the directional albedo of a GGX microfacet BRDF with
// Smith-Schlick visibility (k = alpha / 2, alpha = roughness^2) and Schlick's Fresnel is
// F0 A + B, with A and B functions of n.v and roughness only. The renderer tabulates them in
// a small texture once; the tests use the same function for their references.
#include <Eigen/Core>
#include <vector>

namespace probeless::render {

// (A, B) by importance sampling the GGX lobe with `samples` Hammersley points (Karis's
// IntegrateBRDF). n_dot_v in (0, 1], roughness in [0, 1].
Eigen::Vector2f integrate_split_sum(float n_dot_v, float roughness, int samples = 512);

// size x size table, row-major, two floats per entry: entry (i, j) holds (A, B) at
// n.v = (i + 0.5) / size and roughness = (j + 0.5) / size, texel centres, so that a
// bilinear lookup at (n.v, roughness) interpolates it.
std::vector<float> make_split_sum_table(int size = 32, int samples = 512);

// Bilinear lookup in such a table, clamped at the edges (what the GPU's sampler does).
Eigen::Vector2f lookup_split_sum(const std::vector<float>& table, int size, float n_dot_v,
                                 float roughness);

}  // namespace probeless::render
