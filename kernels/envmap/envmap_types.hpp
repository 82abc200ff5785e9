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

#include "core/camera/kannala_brandt.hpp"
#include "core/cubemap.hpp"
#include "core/image.hpp"

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

// The fisheye as the update kernel sees it: Kannala-Brandt (the sim's equidistant fisheye is
// the k = 0 case) and the rotation from the world into the camera frame. Rotation only: the
// environment is assumed distant, so the camera's offset from the keyframe's position is
// ignored (docs/light-capture.md "Limits").
struct FisheyeView {
  KannalaBrandtParams camera;
  Eigen::Matrix3d R_camera_world = Eigen::Matrix3d::Identity();
};

}  // namespace probeless::envmap
