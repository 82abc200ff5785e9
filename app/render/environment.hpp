#pragma once
// The light an object is rendered under (thesis ch. 6; docs/rendering.md "Environment"): a
// cubemap of linear HDR radiance and its 25 SH coefficients, both in the world frame (z up).
// The image-based materials read the cubemap (prefiltered for rough ones); the diffuse ones
// read the SH. Each frame the caller hands every object the environment of the keyframe
// nearest to it (docs/light-capture.md).
//
// An Environment is immutable once shared: the renderer uploads and prefilters it on first
// use and keeps the result while the shared_ptr lives, so a light update is a new
// Environment (a new shared_ptr), never an edit of the old one.
#include <Eigen/Core>
#include <memory>

#include "core/cubemap.hpp"
#include "core/image.hpp"
#include "core/sh.hpp"

namespace probeless::render {

using ImageRGBAF = Image<float, 4>;
struct EnvironmentLevels;  // environment_map.hpp

struct Environment {
  // Radiance, the six faces stacked top to bottom in OpenGL order (+X, -X, +Y, -Y, +Z, -Z),
  // n x 6n, each face as core/cubemap.hpp orients it: the layout of an environment-map
  // keyframe's texels (kernels/envmap/envmap_types.hpp), so a downloaded keyframe is used as
  // it is. Alpha is ignored (it is the keyframe's texel state there).
  ImageRGBAF faces;
  ShRgb sh;  // radiance coefficients, 5 bands (3 at least), world frame
  // Optional: prepare_levels(*this) (environment_map.hpp), the CPU half of the upload, made by
  // whoever made the Environment off the render thread (the light thread: issue #19's frame
  // p99). The renderer makes them itself when they are absent.
  std::shared_ptr<const EnvironmentLevels> levels;

  int face_size() const { return faces.width(); }
  // Throws std::invalid_argument when the faces are not n x 6n with n >= 1, a radiance is not
  // finite, or the SH have fewer than 3 bands. (Negative radiance reads as 0 on upload.)
  void validate() const;
};

// From a keyframe's texels and its SH (the light estimator computes both).
Environment make_environment(ImageRGBAF faces, const ShRgb& sh);
// From a core Cubemap; the SH are projected from it (5 bands) when not given.
Environment make_environment(const Cubemap& radiance, const ShRgb& sh);
Environment make_environment(const Cubemap& radiance);

// The stacked faces as a core Cubemap (alpha dropped), e.g. for CPU references.
Cubemap to_cubemap(const Environment& environment);

}  // namespace probeless::render
