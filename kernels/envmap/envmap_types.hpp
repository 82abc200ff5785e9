#pragma once
// Environment-map keyframes (thesis ch. 6; docs/light-capture.md): what the update and
// push-pull stages share. A keyframe's texels are one float4 image of n x 6n, the six cube
// faces stacked top to bottom in OpenGL order (core/cubemap.hpp), so texel (x, y) of face f
// is row f n + y. rgb = linear radiance (up to the HDR conversion's constant), alpha = the
// texel's state:
//   alpha > 0   observed: the Kalman rule keeps its relative variance there, the best-score
//               rule the quality of the sample it published;
//   alpha == 0  never observed (or seeded from another keyframe): rgb is whatever push-pull
//               filled in, and the next observation replaces it;
//   alpha < 0   push-pull's temporary mark for border texels copied from a neighbour face
//               (never left behind after a push-pull call).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <optional>

#include "core/cubemap.hpp"
#include "core/image.hpp"
#include "core/room_box.hpp"
#include "kernels/envmap/fisheye_lut.hpp"

namespace probeless::envmap {

using ImageRGBAF = Image<float, 4>;

// Host copy of a keyframe's texels: face_size x 6 face_size, layout as above.
inline ImageRGBAF make_texels(int face_size) {
  return ImageRGBAF(face_size, 6 * face_size);
}
inline int face_size_of(const ImageRGBAF& texels) {
  return texels.width();
}
// The radiance of a texel image as a core Cubemap (alpha dropped).
Cubemap to_cubemap(const ImageRGBAF& texels);
// OpenGL face coordinates (u, v in [0, 1]) -> direction, not normalised, in float as the
// kernels compute it (core's cube_direction is the double-precision original); the CPU
// references of the update and of push-pull share it.
Eigen::Vector3f cube_face_direction(int face, float u, float v);

enum class UpdateRule {
  Kalman,     // per-texel Kalman filter, every frame
  BestScore,  // best-quality sample of each L-M-H-M cycle, published at the cycle's end
};
const char* to_string(UpdateRule rule);

// Parameters of the update rules (docs/light-capture.md says where the defaults come from).
struct UpdateParams {
  UpdateRule rule = UpdateRule::Kalman;
  // Kalman, in relative units (variance of value / true value): the measurement variance of a
  // sample is measurement_sigma^2 / quality; process_sigma^2 is added to each texel's variance
  // per frame (the light may change); an innovation beyond change_sigma standard deviations
  // (of the predicted plus measurement variance) replaces the value (a lamp switched); <= 0
  // turns that off.
  float measurement_sigma = 0.02F;
  float process_sigma = 0.005F;
  float change_sigma = 6.0F;
};

// The room proxy (core/room_box.hpp): keyframe texels then name the point where the ray from
// the keyframe's position leaves the box, not only a direction.
using ::probeless::RoomBox;
// Throws std::invalid_argument unless lo < hi in every axis (all finite).
void validate(const RoomBox& room);

// The fisheye as the update kernel sees it: its lookup table (fisheye_lut.hpp: any camera
// model, built once per camera) and the rotation from the world into the camera frame. Without a
// room box the environment is taken as distant: the camera's offset from the keyframe's position is
// ignored and a texel is its direction. With one, the texel's direction from
// keyframe_position hits the box at a world point p, and the fisheye looks at p from
// `position`, so every frame of a keyframe agrees on what the keyframe's position sees.
struct FisheyeView {
  std::shared_ptr<const FisheyeLut> lut;
  Eigen::Matrix3d R_camera_world = Eigen::Matrix3d::Identity();
  std::optional<RoomBox> room;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();           // the fisheye's centre, world
  Eigen::Vector3d keyframe_position = Eigen::Vector3d::Zero();  // the keyframe's, world
};

// What the update kernel takes for the parallax, in float as both the kernel and the CPU
// reference use it (differences taken in double first, so that metres of offset keep their
// millimetres): the box relative to the keyframe's position, and the keyframe's offset from
// the fisheye. Disabled without a room, or when the keyframe's position is not inside the box
// (no wall ahead of every ray: the texels stay directions).
struct ParallaxConstants {
  bool enabled = false;
  Eigen::Vector3f lo = Eigen::Vector3f::Zero(), hi = Eigen::Vector3f::Zero();  // box - k
  Eigen::Vector3f offset = Eigen::Vector3f::Zero();                            // k - c
};
ParallaxConstants parallax_constants(const FisheyeView& view);
bool inside(const RoomBox& room, const Eigen::Vector3d& p);

// Distance (in units of |d|) along d from a point inside a box to where the ray leaves it;
// lo and hi are the box relative to that point. min over axes of max(lo / d, hi / d): an axis
// d does not move along gives +inf (or NaN for 0/0, which fmax drops). The kernels compute the
// same operations.
float box_exit(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const Eigen::Vector3f& d);

// Direction (not normalised) -> face and face coordinates u, v in [0, 1], in float as
// keyframe_reprojection.cl computes them (core's cube_texel_from_direction).
struct CubeCoord {
  int face = 0;
  float u = 0, v = 0;
};
CubeCoord cube_coord_of(const Eigen::Vector3f& d);

// The world direction the fisheye must look along to see what texel direction d (not
// normalised) shows from the keyframe's position: d itself without parallax; else
// offset + t d with t = box_exit (the wall point seen from the fisheye's centre).
Eigen::Vector3f parallax_direction(const ParallaxConstants& p, const Eigen::Vector3f& d);

}  // namespace probeless::envmap
