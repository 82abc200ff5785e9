#pragma once
// What the glTF and OBJ loaders share (not part of the mesh API).
#include <Eigen/Core>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "app/render/mesh.hpp"
#include "core/read_limits.hpp"

namespace probeless::render::detail {

// The turn from a model file's axes to the world's: y-up files are turned +90 degrees about
// x, (x, y, z) -> (x, -z, y); identity when options.y_up is false.
Eigen::Matrix3d model_axes_to_world(const ModelLoadOptions& options);

// A mesh whose per-vertex colours are all the same carries that colour as base_colour and
// no per-vertex colours.
void collapse_uniform_colours(Mesh& mesh);

// The parsers (tinygltf, tinyobjloader) hold a whole model file in memory: one over
// read_limits::kMaxModelFileBytes is refused before they read it. Missing: "no such file".
inline void check_model_file(const std::filesystem::path& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw std::runtime_error(path.string() + ": no such file");
  if (size > static_cast<std::uintmax_t>(read_limits::kMaxModelFileBytes))
    throw std::runtime_error(path.string() + ": " + std::to_string(size) +
                             " bytes, over the limit of " +
                             std::to_string(read_limits::kMaxModelFileBytes) + " for a model file");
}

}  // namespace probeless::render::detail
