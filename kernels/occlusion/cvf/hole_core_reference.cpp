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

int near_rim_radius(int width) {
  return std::max(kNearRimMeasuredPx, hole_core_radius(kNearRimMeasuredPx, width));
}

DepthImage mark_near_occluders_reference(const DepthImage& depth, int radius,
                                         const ImageRGB8* colour) {
  DepthImage out = fill_hole_cores_reference(depth, radius, colour);
  if (radius <= 0) return out;
  const DepthImage filled = out;
  const int w = depth.width(), h = depth.height();
  const int m = near_rim_radius(w);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (depth.at(x, y) != 0 || filled.at(x, y) == kNearHoleDepthMm) continue;
      int n_core = 0, core_sum[3] = {0, 0, 0};
      for (int j = std::max(0, y - radius); j <= std::min(h - 1, y + radius); ++j)
        for (int k = std::max(0, x - radius); k <= std::min(w - 1, x + radius); ++k) {
          if (filled.at(k, j) != kNearHoleDepthMm) continue;
          ++n_core;
          if (colour)
            for (int c = 0; c < 3; ++c) core_sum[c] += colour->at(k, j, c);
        }
      if (n_core == 0) continue;
      if (colour) {
        int n_meas = 0, meas_sum[3] = {0, 0, 0};
        for (int j = std::max(0, y - m); j <= std::min(h - 1, y + m); ++j)
          for (int k = std::max(0, x - m); k <= std::min(w - 1, x + m); ++k) {
            if (depth.at(k, j) == 0) continue;
            ++n_meas;
            for (int c = 0; c < 3; ++c) meas_sum[c] += colour->at(k, j, c);
          }
        const int c[3] = {colour->at(x, y, 0), colour->at(x, y, 1), colour->at(x, y, 2)};
        if (!rim_takes_core_colour(c, n_core, core_sum, n_meas, meas_sum)) continue;
      }
      out.at(x, y) = kNearHoleDepthMm;
    }
  return out;
}

}  // namespace probeless::occlusion
