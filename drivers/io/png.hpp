#pragma once
// PNG files through libpng (docs/formats.md "PNG conventions"). Readers convert what is safe
// to convert (palette, gray, alpha, 16-bit -> 8-bit) for the 8-bit types and insist on the
// exact layout for the 16-bit ones, whose values are measurements (depth in mm, raw sensor
// values). Every failure is an ImageFileError that names the file; nothing else escapes.
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/image.hpp"

namespace probeless {

class ImageFileError : public std::runtime_error {
 public:
  ImageFileError(std::filesystem::path path, const std::string& what)
      : std::runtime_error(path.string() + ": " + what), path_(std::move(path)) {}
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Any PNG; gray, palette and 16-bit are converted, alpha is dropped (not composited).
ImageRGB8 read_png_rgb8(const std::filesystem::path& path);
// Any PNG; colour is converted to gray by Rec. 709 luma, alpha is dropped.
ImageGray8 read_png_gray8(const std::filesystem::path& path);
// 16-bit single-channel PNG only; values exactly as stored (depth: mm, 0 = unknown).
DepthImage read_png_depth16(const std::filesystem::path& path);
// 16-bit RGB PNG only (no alpha); values exactly as stored.
ImageRGB16 read_png_rgb16(const std::filesystem::path& path);

// Fast compression (recordings are written at frame rate). The file appears complete or not
// at all: it is written to "<name>.tmp" and renamed.
void write_png(const std::filesystem::path& path, const ImageRGB8& image);
void write_png(const std::filesystem::path& path, const ImageGray8& image);
void write_png(const std::filesystem::path& path, const DepthImage& image);
void write_png(const std::filesystem::path& path, const ImageRGB16& image);
void write_png(const std::filesystem::path& path, const ImageRGBA8& image);

// The same encoding in memory (HTTP snapshots, tests).
std::vector<std::uint8_t> encode_png(const ImageRGB8& image);

}  // namespace probeless
