#pragma once
// Plain C++ of envmap_update.cl, step for step in float, for the kernel tests.
#include <Eigen/Core>
#include <optional>

#include "kernels/envmap/envmap_types.hpp"

namespace probeless::envmap {

// The converted image's sample (rgb, quality) seen along a world direction, or nullopt when
// the fisheye does not see it or a neighbour pixel is unusable.
std::optional<Eigen::Vector4f> sample_fisheye_reference(const ImageRGBAF& image,
                                                        const FisheyeView& view,
                                                        const Eigen::Vector3f& world_direction);

// The texel's world direction exactly as the kernel computes it (not normalised).
Eigen::Vector3f texel_direction_reference(int face, int x, int y, int n);

void envmap_update_reference(const ImageRGBAF& image, const FisheyeView& view,
                             const UpdateParams& params, bool publish, ImageRGBAF& texels,
                             ImageRGBAF& pending);

}  // namespace probeless::envmap
