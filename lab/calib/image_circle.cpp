#include "lab/calib/image_circle.hpp"

#include <algorithm>
#include <cmath>

namespace probeless::calib {

double image_circle_radius(const std::vector<ImageGray8>& images, double fx, double fy, double cx,
                           double cy) {
  if (images.empty() || !(fx > 0) || !(fy > 0)) return 0;
  const int w = images.front().width(), h = images.front().height();
  // Rings one pixel wide (in units of the mean focal length) out to the farthest corner.
  const double f = 0.5 * (fx + fy);
  double corner = 0;
  for (double u : {-0.5, w - 0.5})
    for (double v : {-0.5, h - 0.5})
      corner = std::max(corner, std::hypot((u - cx) / fx, (v - cy) / fy));
  const auto rings = static_cast<std::size_t>(std::ceil(corner * f)) + 1;
  std::vector<double> sum(rings, 0.0);
  std::vector<double> count(rings, 0.0);
  for (const ImageGray8& image : images) {
    if (image.width() != w || image.height() != h) continue;
    for (int y = 0; y < h; ++y) {
      const std::uint8_t* row = image.row(y);
      for (int x = 0; x < w; ++x) {
        const auto ring = static_cast<std::size_t>(std::hypot((x - cx) / fx, (y - cy) / fy) * f);
        sum[std::min(ring, rings - 1)] += row[x];
        count[std::min(ring, rings - 1)] += 1;
      }
    }
  }
  const auto mean = [&](std::size_t i) { return count[i] > 0 ? sum[i] / count[i] : -1.0; };
  // The inner image: the rings inside half the corner radius; the rim: the outermost rings
  // that hold pixels (the corners of the frame).
  double inner = 0, inner_n = 0;
  for (std::size_t i = 0; i < rings / 2; ++i)
    if (count[i] > 0) {
      inner += sum[i];
      inner_n += count[i];
    }
  std::size_t last = rings - 1;
  while (last > 0 && count[last] == 0) --last;
  if (inner_n == 0 || last < rings / 2) return 0;
  inner /= inner_n;
  const double rim = mean(last);
  // Dark means well below the image: a rim within a third of the image's brightness is just
  // a dim corner of a frame the circle fills.
  if (!(rim < inner / 3)) return 0;
  const double threshold = 0.5 * (inner + rim);
  for (std::size_t i = rings / 2; i <= last; ++i)
    if (count[i] > 0 && mean(i) < threshold)
      return std::max(0.0, (static_cast<double>(i) - 1.0) / f);
  return 0;
}

}  // namespace probeless::calib
