#pragma once
// What the glTF and OBJ loaders share (not part of the mesh API).
#include <Eigen/Core>

#include "app/render/mesh.hpp"

namespace probeless::render::detail {

// The turn from a model file's axes to the world's: y-up files are turned +90 degrees about
// x, (x, y, z) -> (x, -z, y); identity when options.y_up is false.
Eigen::Matrix3d model_axes_to_world(const ModelLoadOptions& options);

// A mesh whose per-vertex colours are all the same carries that colour as base_colour and
// no per-vertex colours.
void collapse_uniform_colours(Mesh& mesh);

}  // namespace probeless::render::detail
