#pragma once
// Captured V4L2 pixels -> the FisheyeFrame's linear raw RGB16 (docs/drivers.md "Formats").
// No V4L2 headers here: the source maps the fourcc and the colorimetry to these enums, so the
// conversions are unit-tested on any machine.
//
// Raw Bayer is linear already: it is demosaiced (bilinear) and kept at its bit depth (8, or 12
// for 10/12/16-bit containers, scaled by a power of two so E stays proportional). YUYV and
// RGB24 are display-referred, gamma-coded 8-bit: they are decoded to R'G'B' and linearised
// with the transfer function the driver reports (sRGB or Rec. 709), through a 256-entry table
// into 12 bit. That linearisation is an assumption about the camera's processing (its tone
// curve is rarely exactly the standard one), so HDR from such a camera is approximate.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/image.hpp"

namespace probeless::v4l2 {

enum class PixelLayout {
  Bayer8,   // one byte per sample
  Bayer16,  // little-endian 16-bit containers with `bits` significant low bits (10, 12, 16)
  RGB24,
  BGR24,
  YUYV,
};

// Colour of the top-left sample of the 2x2 Bayer tile, then its right neighbour, etc.
enum class BayerOrder { RGGB, BGGR, GRBG, GBRG };

enum class TransferFunction { Srgb, Rec709, Linear };
enum class YcbcrEncoding { Bt601, Bt709 };

struct PixelFormat {
  PixelLayout layout = PixelLayout::YUYV;
  BayerOrder bayer = BayerOrder::RGGB;
  int bits = 8;                    // significant bits per Bayer sample (Bayer16 only)
  std::size_t bytes_per_line = 0;  // stride of the captured image (>= width * bytes per pixel)
  TransferFunction transfer = TransferFunction::Srgb;
  YcbcrEncoding encoding = YcbcrEncoding::Bt601;
  bool full_range = false;  // YCbCr quantisation: full (0..255) or limited (16..235/240)
};

// The bit depth of the converted frame: 8 for Bayer8, 12 for everything else.
int output_bit_depth(const PixelFormat& format);

// The bytes one captured frame of width x height needs (bytes_per_line * height).
std::size_t frame_bytes(const PixelFormat& format, int height);

// Converts one captured frame into `out` (resized to width x height). Throws
// std::invalid_argument when `in` is shorter than frame_bytes() or the size is odd where the
// layout needs pairs (Bayer tiles, YUYV macropixels).
void convert_to_linear_rgb16(std::span<const std::uint8_t> in, const PixelFormat& format, int width,
                             int height, ImageRGB16& out);

// Linear value in [0, 1] of an 8-bit code under `transfer` (exposed for the tests).
double linearise(std::uint8_t code, TransferFunction transfer);

}  // namespace probeless::v4l2
