#pragma once
// A keyframe in the inverse-compositional form: the points chosen on it at each pyramid level
// with everything that does not depend on the current frame (3D point, intensity, normal and
// both Jacobians) computed once when the frame becomes a keyframe.
#include <CL/opencl.hpp>
#include <array>
#include <vector>

#include "core/pose.hpp"
#include "core/time.hpp"
#include "kernels/tracking/frame_pyramid.hpp"

namespace probeless::tracking {

// 24 floats, the layout the device kernels read and write (tracking.cl).
struct TrackPoint {
  float x, y, z;     // keyframe camera coordinates, metres
  float intensity;   // grey level on the keyframe
  float nx, ny, nz;  // surface normal towards the camera
  float has_normal;  // 1: the point-to-plane residual is used
  float j_photo[6];  // d(I_kf(pi(exp(xi) P))) / d xi at xi = 0, xi = (v, w)
  float j_geo[6];    // -[n, P x n] / z^2 (the depth residual's Jacobian, noise-scaled)
  float inv_z2;      // 1 / z^2: Kinect depth noise grows with z^2 (Khoshelham 2012)
  float valid;       // 1: a point (the device selection leaves 0 where a block has none)
  float pad[2];
};
static_assert(sizeof(TrackPoint) == 24 * sizeof(float));

struct Keyframe {
  Pose T_world_keyframe;
  TimestampNs timestamp_ns = 0;
  int id = 0;  // the frame (counted from reset()) that became this keyframe
  // Made without a known angular velocity (a first frame, or one just after a loss) under a
  // rolling shutter: its points still carry the readout's shear until one is measured.
  bool shear_pending = false;
  std::vector<LevelCamera> cameras;             // per level, as the frame's pyramid
  std::vector<std::vector<TrackPoint>> points;  // per level
  std::vector<::cl::Buffer> device_points;      // per level, filled by the device path
};

// The side of the blocks that each give one point, for a level of width x height.
int point_block_size(int width, int height, int max_points);

// Chooses and precomputes the points of every level (CPU; once per keyframe), then
// undo_rolling_shutter(readout_rotation).
Keyframe make_keyframe(const FramePyramid& pyramid, const Pose& T_world_keyframe,
                       int max_points_per_level, const std::array<float, 3>& readout_rotation);

// Rolling shutter: each point was seen by its row, exposed s = v/h - 1/2 of the readout away
// from the middle row, when the camera had turned by s * readout_rotation (rad, camera axes):
// its position and normal are moved into the middle row's camera (small angle). The
// Jacobians are kept: the rotation is a fraction of a degree to a degree or two.
void undo_rolling_shutter(Keyframe& keyframe, const std::array<float, 3>& readout_rotation);

}  // namespace probeless::tracking
