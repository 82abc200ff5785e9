#include "kernels/occlusion/cvf/hole_core_reference.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace probeless::occlusion {

int hole_core_radius(int radius_at_640, int width) {
  if (radius_at_640 <= 0 || width <= 0) return 0;
  return std::max(1, static_cast<int>(std::lround(double(radius_at_640) * width / 640.0)));
}

DepthImage fill_hole_cores_reference(const DepthImage& depth, int radius, const ImageRGB8* colour) {
  if (radius <= 0) return depth;
  const int w = depth.width(), h = depth.height();
  if (colour && (colour->width() != w || colour->height() != h))
    throw std::invalid_argument("hole cores: colour and depth sizes differ");
  auto hole = [&](int x, int y) {
    if (depth.at(x, y) != 0) return false;
    if (!colour) return true;
    const auto* c = &colour->at(x, y, 0);
    return !far_hole_colour(c[0], c[1], c[2]);
  };
  // Rows, then columns: a window is all hole iff every row segment in it is.
  Image<std::uint8_t, 1> rows(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool all = true;
      for (int k = std::max(0, x - radius); k <= std::min(w - 1, x + radius) && all; ++k)
        all = hole(k, y);
      rows.at(x, y) = all ? 1 : 0;
    }
  DepthImage out = depth;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool all = true;
      for (int k = std::max(0, y - radius); k <= std::min(h - 1, y + radius) && all; ++k)
        all = rows.at(x, k) != 0;
      if (all) out.at(x, y) = kNearHoleDepthMm;
    }
  return out;
}

DepthImage mark_near_occluders_reference(const DepthImage& depth, int radius,
                                         const ImageRGB8* colour) {
  DepthImage out = fill_hole_cores_reference(depth, radius, colour);
  if (radius <= 0) return out;
  const DepthImage filled = out;
  const int w = depth.width(), h = depth.height();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (depth.at(x, y) != 0) continue;
      bool any = false;
      for (int j = std::max(0, y - radius); j <= std::min(h - 1, y + radius) && !any; ++j)
        for (int k = std::max(0, x - radius); k <= std::min(w - 1, x + radius) && !any; ++k)
          any = filled.at(k, j) == kNearHoleDepthMm;
      if (any) out.at(x, y) = kNearHoleDepthMm;
    }
  return out;
}

}  // namespace probeless::occlusion
