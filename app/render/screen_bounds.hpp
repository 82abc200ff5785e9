#pragma once
// Which pixels the virtual objects can cover in a view, so that the renderer clears, draws and
// reads back only those (docs/rendering.md "Only the objects' pixels"). A frame's HDR layer is
// 4.9 MB of radiance and 1.2 MB of depth at 640x480; the objects cover a fraction of it, and
// clearing and copying the rest was most of the render stage's CPU (docs/performance.md).
#include <Eigen/Core>

#include "core/camera/pinhole.hpp"

namespace probeless::render {

// The pixels [x0, x1) x [y0, y1) of an image, rows counted from the top; empty when either
// span is.
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  bool empty() const { return x1 <= x0 || y1 <= y0; }
  int width() const { return empty() ? 0 : x1 - x0; }
  int height() const { return empty() ? 0 : y1 - y0; }
  bool contains_row(int y) const { return !empty() && y >= y0 && y < y1; }
  bool operator==(const PixelRect&) const = default;

  static PixelRect whole(int width, int height) { return {0, 0, width, height}; }
};

// The smallest rectangle holding both (an empty one holds nothing).
PixelRect unite(const PixelRect& a, const PixelRect& b);
// The pixels in both.
PixelRect intersect(const PixelRect& a, const PixelRect& b);

// The pixels where any point of the box [lo, hi] (object frame) can land after
// `camera_from_object` (scale included) and the pinhole `k`, clipped at `near_m` as the
// renderer's projection clips: the projections of the box's corners in front of the near
// plane and of its edges' crossings of it bound the projection of the clipped box (a convex
// set), widened by one pixel so that rasterisation at the boundary stays inside. Clamped to
// the image; empty when the whole box is behind the near plane or off the image.
PixelRect projected_box(const PinholeIntrinsics& k, const Eigen::Matrix4d& camera_from_object,
                        const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, double near_m);

}  // namespace probeless::render
