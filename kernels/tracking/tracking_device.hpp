#pragma once
// The device side of the dense tracker (tracking.cl): the current frame's pyramid (grey,
// metres, 2x2 averaging) stays on the device, and each Gauss-Newton iteration reduces the
// keyframe points' residuals to partial sums per work-group, added up on the host.
#include <vector>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"
#include "kernels/tracking/keyframe.hpp"
#include "kernels/tracking/normal_equations.hpp"

namespace probeless::tracking {

struct DenseTrackerParams;

class TrackingDevice {
 public:
  explicit TrackingDevice(ComputeContext& ctx);

  // The undistortion_map() build_pyramid() applies from now on (empty: none).
  void set_undistortion(const std::vector<float>& map);
  // The frame's pyramid on the device.
  void build_pyramid(const ImageRGB8& colour, const DepthImage& depth_mm,
                     const PinholeIntrinsics& camera, const DenseTrackerParams& params);
  // The last built pyramid on the host (when the frame becomes a keyframe, and for tests).
  void download_pyramid(FramePyramid& pyramid);
  // The last built pyramid as a keyframe: points chosen and precomputed on the device (the
  // twin of make_keyframe()), compacted on the host and uploaded.
  Keyframe make_keyframe(const Pose& T_world_keyframe, int max_points_per_level,
                         const std::array<float, 3>& readout_rotation);
  // Copies the keyframe's points to the device once (no-op when already there).
  void upload_points(Keyframe& keyframe);
  // One iteration's sums at `level` of the last built pyramid.
  NormalSums accumulate(const Keyframe& keyframe, int level, const IterationParams& params);

 private:
  struct Level {
    LevelCamera camera;
    DeviceImage<float, 1> intensity, depth_m;
  };
  ComputeContext& ctx_;
  ::cl::Kernel finest_, undistort_, halve_, accumulate_, select_;
  ::cl::Buffer slots_;  // select_points' output, one point per block
  std::size_t slots_capacity_ = 0;
  std::vector<TrackPoint> slots_host_;
  Level distorted_;  // the finest level before undistortion
  ::cl::Buffer undistort_map_;
  std::size_t map_size_ = 0;  // floats in undistort_map_; 0: no undistortion
  DeviceImage<std::uint8_t, 3> colour_;
  DeviceImage<std::uint16_t, 1> depth_mm_;
  std::vector<Level> levels_;
  ::cl::Buffer partial_;
  std::vector<float> partial_host_;
};

}  // namespace probeless::tracking
