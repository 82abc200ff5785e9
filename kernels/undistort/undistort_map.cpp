#include "kernels/undistort/undistort_map.hpp"

namespace probeless {

std::optional<UndistortMap> build_undistort_map(const PinholeCamera& camera) {
  if (camera.distortion().is_zero()) return std::nullopt;
  const PinholeIntrinsics& k = camera.intrinsics();
  UndistortMap map{Image<float, 2>(k.width, k.height)};
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) {
      const Eigen::Vector3d ray((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0);
      const auto px = camera.project(ray);
      map.source.at(x, y, 0) = px ? static_cast<float>(px->x()) : UndistortMap::kInvalid;
      map.source.at(x, y, 1) = px ? static_cast<float>(px->y()) : UndistortMap::kInvalid;
    }
  return map;
}

}  // namespace probeless
