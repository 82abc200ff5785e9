#include "kernels/envmap/keyframe_reprojection.hpp"

#include <stdexcept>

#include "kernels/envmap/keyframe_reprojection_cl.hpp"

namespace probeless::envmap {

ParallaxConstants reprojection_constants(const std::optional<RoomBox>& room,
                                         const Eigen::Vector3d& keyframe_position,
                                         const Eigen::Vector3d& target) {
  ParallaxConstants c;
  if (!room || !inside(*room, keyframe_position) || !inside(*room, target)) return c;
  c.enabled = true;
  c.lo = (room->lo - target).cast<float>();
  c.hi = (room->hi - target).cast<float>();
  c.offset = (target - keyframe_position).cast<float>();
  return c;
}

KeyframeReprojection::KeyframeReprojection(ComputeContext& ctx)
    : ctx_(ctx),
      kernel_(ctx.kernel("keyframe_reprojection", cl_source::keyframe_reprojection, {},
                         "reproject_keyframe")) {}

void KeyframeReprojection::run(const DeviceImage<float, 4>& texels,
                               const Eigen::Vector3d& keyframe_position,
                               const std::optional<RoomBox>& room, const Eigen::Vector3d& target,
                               int m, int samples, DeviceImage<float, 4>& out) {
  const int n = texels.width();
  if (texels.height() != 6 * n)
    throw std::invalid_argument("KeyframeReprojection: texels must be n x 6n");
  if (m < 1 || samples < 1)
    throw std::invalid_argument("KeyframeReprojection: face size and samples must be >= 1");
  out.resize(ctx_.context(), m, 6 * m);
  if (texels.empty()) return;
  const ParallaxConstants p = reprojection_constants(room, keyframe_position, target);
  const auto f4 = [](const Eigen::Vector3f& v) { return cl_float4{{v.x(), v.y(), v.z(), 0.0F}}; };
  int a = 0;
  kernel_.setArg(a++, texels.buffer());
  kernel_.setArg(a++, n);
  kernel_.setArg(a++, out.buffer());
  kernel_.setArg(a++, m);
  kernel_.setArg(a++, samples);
  kernel_.setArg(a++, p.enabled ? 1 : 0);
  kernel_.setArg(a++, f4(p.lo));
  kernel_.setArg(a++, f4(p.hi));
  kernel_.setArg(a++, f4(p.offset));
  ctx_.run_2d(kernel_, m, 6 * m);
}

}  // namespace probeless::envmap
