#pragma once
// HDR images: Radiance RGBE (.hdr, .pic) through the codec in hdr_radiance.cpp and OpenEXR
// (.exr) through the OpenEXR library. The format follows the file extension (any case). Every
// failure is an ImageFileError (drivers/io/png.hpp) naming the file.
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "core/image.hpp"
#include "drivers/io/png.hpp"  // ImageFileError

namespace probeless {

// Linear radiance, row 0 at the top. Radiance files: flat, old-style and new-style RLE
// scanlines; the EXPOSURE header is undone (values are divided by it, as the format says).
// OpenEXR files: half or float R, G, B channels (or Y, copied to all three) of the data window.
ImageRGBF read_hdr_image(const std::filesystem::path& path);

struct HdrWriteOptions {
  bool exr_half = false;  // OpenEXR: 16-bit half channels (half the size, 11-bit mantissa)
};

// Radiance: new-style RLE, values <= 0 or NaN stored as 0. OpenEXR: 32-bit float (or half)
// R, G, B, ZIP compressed. The file appears complete or not at all ("<name>.tmp", renamed).
void write_hdr_image(const std::filesystem::path& path, const ImageRGBF& image,
                     HdrWriteOptions options = {});

// The Radiance codec in memory (tests, fuzzing); `name` is what errors call the data.
ImageRGBF decode_radiance_hdr(std::span<const std::uint8_t> bytes,
                              const std::filesystem::path& name);
std::vector<std::uint8_t> encode_radiance_hdr(const ImageRGBF& image);

}  // namespace probeless
