#include "app/render/screen_bounds.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace probeless::render {

PixelRect projected_box(const PinholeIntrinsics& k, const Eigen::Matrix4d& camera_from_object,
                        const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, double near_m) {
  std::array<Eigen::Vector3d, 8> corners;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector4d p((i & 1 ? hi : lo).x(), (i & 2 ? hi : lo).y(), (i & 4 ? hi : lo).z(),
                            1.0);
    corners[static_cast<std::size_t>(i)] = (camera_from_object * p).head<3>();
  }
  double u0 = std::numeric_limits<double>::infinity(), v0 = u0;
  double u1 = -u0, v1 = -u0;
  auto add = [&](const Eigen::Vector3d& p) {  // p.z() >= near_m
    const double u = k.fx * p.x() / p.z() + k.cx, v = k.fy * p.y() / p.z() + k.cy;
    u0 = std::min(u0, u), u1 = std::max(u1, u);
    v0 = std::min(v0, v), v1 = std::max(v1, v);
  };
  for (const auto& c : corners)
    if (c.z() >= near_m) add(c);
  // The twelve edges join corners whose indices differ in one bit.
  for (int a = 0; a < 8; ++a)
    for (int bit = 1; bit < 8; bit <<= 1) {
      const int b = a | bit;
      if (b == a) continue;
      const Eigen::Vector3d& p = corners[static_cast<std::size_t>(a)];
      const Eigen::Vector3d& q = corners[static_cast<std::size_t>(b)];
      if ((p.z() < near_m) == (q.z() < near_m)) continue;
      const double t = (near_m - p.z()) / (q.z() - p.z());
      Eigen::Vector3d x = p + t * (q - p);
      x.z() = near_m;  // exactly on the plane, whatever the rounding
      add(x);
    }
  if (!(u0 <= u1 && v0 <= v1)) return {};  // the box is behind the near plane
  // A pixel (column i) is drawn when its centre, u = i, is inside a triangle: columns
  // ceil(u0)..floor(u1). One more on each side for the rasteriser's rounding. Clamped in
  // double first: a crossing of the near plane can project far outside the image.
  auto column = [](double u, int size) {
    return static_cast<int>(std::floor(std::clamp(u, -2.0, static_cast<double>(size) + 2.0)));
  };
  const PixelRect box{column(u0, k.width) - 1, column(v0, k.height) - 1, column(u1, k.width) + 2,
                      column(v1, k.height) + 2};
  return intersect(box, PixelRect::whole(k.width, k.height));
}

}  // namespace probeless::render
