#pragma once
// Ground-truth light cubemaps in recordings: a PFM (Portable Float Map, 32-bit float RGB)
// with the six faces stacked vertically in OpenGL order (+X at the top), each face with its
// rows top to bottom as in core/cubemap.hpp. PFM stores float bits as they are, so truth
// replays exactly. Failures are ImageFileError naming the file.
#include <filesystem>

#include "core/cubemap.hpp"

namespace probeless::replay {

void write_light_cubemap(const std::filesystem::path& path, const Cubemap& cubemap);
Cubemap read_light_cubemap(const std::filesystem::path& path);

}  // namespace probeless::replay
