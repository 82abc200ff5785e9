#include "kernels/undistort/undistort_reference.hpp"

#include <cmath>

namespace probeless {

namespace {
constexpr float kValidAbove = UndistortMap::kInvalid / 10;  // undistort.cl's VALID_ABOVE
}

ImageRGB8 undistort_colour_reference(const ImageRGB8& in, const UndistortMap& map) {
  const int w = in.width(), h = in.height();
  ImageRGB8 out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float sx = map.source.at(x, y, 0), sy = map.source.at(x, y, 1);
      const float fx0 = std::floor(sx), fy0 = std::floor(sy);
      if (!(sx > kValidAbove && fx0 >= 0.0F && fy0 >= 0.0F && fx0 + 1.0F < static_cast<float>(w) &&
            fy0 + 1.0F < static_cast<float>(h))) {
        for (int c = 0; c < 3; ++c) out.at(x, y, c) = 0;
        continue;
      }
      const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
      const float ax = sx - fx0, ay = sy - fy0;
      for (int c = 0; c < 3; ++c) {
        const float a = in.at(x0, y0, c), b = in.at(x0 + 1, y0, c);
        const float cc = in.at(x0, y0 + 1, c), d = in.at(x0 + 1, y0 + 1, c);
        const float top = a + ax * (b - a), bottom = cc + ax * (d - cc);
        const float v = top + ay * (bottom - top) + 0.5F;
        out.at(x, y, c) = static_cast<std::uint8_t>(v >= 255.0F ? 255.0F : (v > 0 ? v : 0.0F));
      }
    }
  return out;
}

DepthImage undistort_depth_reference(const DepthImage& in, const UndistortMap& map) {
  const int w = in.width(), h = in.height();
  DepthImage out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float sx = map.source.at(x, y, 0), sy = map.source.at(x, y, 1);
      const float nx = std::floor(sx + 0.5F), ny = std::floor(sy + 0.5F);
      const bool inside = sx > kValidAbove && nx >= 0.0F && ny >= 0.0F &&
                          nx < static_cast<float>(w) && ny < static_cast<float>(h);
      out.at(x, y) = inside ? in.at(static_cast<int>(nx), static_cast<int>(ny)) : 0;
    }
  return out;
}

}  // namespace probeless
