#pragma once
// libcamera pixel formats to the V4L2 source's conversions (drivers/v4l2/pixel_convert.hpp):
// libcamera names DRM fourccs, so its BGR888 is V4L2's RGB24 (bytes R, G, B) and RGB888 is
// BGR24. Only layouts pixel_convert handles are mapped; packed CSI-2 and planar YUV are not.
#include <libcamera/pixel_format.h>
#include <libcamera/stream.h>

#include <optional>

#include "drivers/v4l2/pixel_convert.hpp"

namespace probeless::libcam {

// The layout of `format` (bytes_per_line and colorimetry left at their defaults), or nothing
// when the conversion does not handle it.
std::optional<v4l2::PixelFormat> pixel_layout(const libcamera::PixelFormat& format);

// Preference among convertible formats, best first (0): linear raw Bayer (12, 10, 16, then 8
// bit) before the gamma-coded RGB24/BGR24 and YUYV, as for V4L2 (docs/drivers.md "Formats").
// -1 when not convertible.
int format_rank(const libcamera::PixelFormat& format);

// The full conversion description of a configured stream: layout, stride and the transfer
// function, encoding and range of its colour space (sRGB when the pipeline gives none).
v4l2::PixelFormat stream_pixel_format(const libcamera::StreamConfiguration& config);

}  // namespace probeless::libcam
