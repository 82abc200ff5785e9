#pragma once
// Plain C++ of keyframe_reprojection.cl, step for step in float, for the tests and for
// `eval light` (which reprojects host copies).
#include <Eigen/Core>
#include <optional>

#include "kernels/envmap/envmap_types.hpp"

namespace probeless::envmap {

ImageRGBAF reproject_keyframe_reference(const ImageRGBAF& texels,
                                        const Eigen::Vector3d& keyframe_position,
                                        const std::optional<RoomBox>& room,
                                        const Eigen::Vector3d& target, int m, int samples);

}  // namespace probeless::envmap
