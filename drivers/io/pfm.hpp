#pragma once
// Portable Float Map (PFM): the Middlebury 2014 disparity format. A text header
// ("Pf" gray / "PF" colour, "width height", scale whose sign gives the byte order: negative =
// little-endian) and then rows of 32-bit floats, bottom row first. Failures are
// ImageFileError naming the file.
#include <filesystem>

#include "core/image.hpp"
#include "drivers/io/png.hpp"

namespace probeless {

// Gray PFM ("Pf") as stored values (Middlebury: disparity in px, inf = unknown), top row first.
ImageF read_pfm(const std::filesystem::path& path);

// Little-endian gray PFM, for tests and tools.
void write_pfm(const std::filesystem::path& path, const ImageF& image);

}  // namespace probeless
