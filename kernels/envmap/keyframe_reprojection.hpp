#pragma once
// A keyframe seen from another position through the room box (keyframe_reprojection.cl;
// docs/light-capture.md "Parallax"): what an object away from the keyframe's position sees,
// for comparing with the truth there (eval light) and for the object's SH (LightEstimator).
#include <Eigen/Core>

#include "kernels/envmap/envmap_types.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::envmap {

// What the kernel takes, in float (differences in double first); parallax is off when there
// is no room or either position is outside it (the texels are then kept as directions).
ParallaxConstants reprojection_constants(const std::optional<RoomBox>& room,
                                         const Eigen::Vector3d& keyframe_position,
                                         const Eigen::Vector3d& target);

class KeyframeReprojection {
 public:
  explicit KeyframeReprojection(ComputeContext& ctx);

  // texels: the keyframe (n x 6n). out: m x 6m, each texel the mean of samples x samples
  // nearest keyframe texels seen from `target` (m x samples <= n keeps every keyframe texel
  // reachable); alpha 1 when all of them were observed, else 0. Enqueues only.
  void run(const DeviceImage<float, 4>& texels, const Eigen::Vector3d& keyframe_position,
           const std::optional<RoomBox>& room, const Eigen::Vector3d& target, int m, int samples,
           DeviceImage<float, 4>& out);

 private:
  ComputeContext& ctx_;
  ::cl::Kernel kernel_;
};

}  // namespace probeless::envmap
