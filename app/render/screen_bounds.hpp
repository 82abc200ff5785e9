#pragma once
// Which pixels the virtual objects can cover in a view, so that the renderer clears, draws and
// reads back only those (docs/rendering.md "Only the objects' pixels"). A frame's HDR layer is
// 4.9 MB of radiance and 1.2 MB of depth at 640x480; the objects cover a fraction of it, and
// clearing and copying the rest was most of the render stage's CPU (docs/performance.md).
#include <Eigen/Core>

#include "core/camera/pinhole.hpp"
#include "core/pixel_rect.hpp"

namespace probeless::render {

using probeless::intersect;
using probeless::PixelRect;
using probeless::unite;

// The pixels where any point of the box [lo, hi] (object frame) can land after
// `camera_from_object` (scale included) and the pinhole `k`, clipped at `near_m` as the
// renderer's projection clips: the projections of the box's corners in front of the near
// plane and of its edges' crossings of it bound the projection of the clipped box (a convex
// set), widened by one pixel so that rasterisation at the boundary stays inside. Clamped to
// the image; empty when the whole box is behind the near plane or off the image.
PixelRect projected_box(const PinholeIntrinsics& k, const Eigen::Matrix4d& camera_from_object,
                        const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, double near_m);

}  // namespace probeless::render
