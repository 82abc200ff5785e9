#pragma once
// V4L2 fourccs and colorimetry -> the conversions of pixel_convert.hpp. Internal to
// drivers/v4l2.
#include <linux/videodev2.h>

#include <cstdint>
#include <optional>
#include <string>

#include "drivers/v4l2/pixel_convert.hpp"

namespace probeless::v4l2 {

// The layout (and Bayer order/bits) of a fourcc we can convert, or nothing.
std::optional<PixelFormat> layout_of(std::uint32_t fourcc);

// Which of two convertible formats to prefer: lower is better. Linear raw first (more bits
// first), then the gamma-coded ones (RGB before YUYV: no chroma subsampling).
int preference(const PixelFormat& format);

// Fills bytes_per_line and the colorimetry (transfer function, YCbCr encoding and range) of
// `format` from what S_FMT returned; V4L2's "default" values resolve from the colorspace as
// the V4L2 specification's tables say.
void apply_colourimetry(const v4l2_pix_format& pix, PixelFormat& format);

std::string fourcc_text(std::uint32_t fourcc);
std::uint32_t fourcc_from_text(const std::string& text);  // exactly four characters

}  // namespace probeless::v4l2
