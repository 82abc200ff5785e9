#include "drivers/libcamera/libcamera_format_map.hpp"

#include <libcamera/color_space.h>
#include <libcamera/formats.h>

#include <array>

namespace probeless::libcam {
namespace {

using v4l2::BayerOrder;
using v4l2::PixelLayout;
namespace f = libcamera::formats;

struct Entry {
  libcamera::PixelFormat format;
  PixelLayout layout;
  BayerOrder order;
  int bits;
};

// In preference order (format_rank is the index).
const std::array kEntries{
    Entry{f::SRGGB12, PixelLayout::Bayer16, BayerOrder::RGGB, 12},
    Entry{f::SGRBG12, PixelLayout::Bayer16, BayerOrder::GRBG, 12},
    Entry{f::SGBRG12, PixelLayout::Bayer16, BayerOrder::GBRG, 12},
    Entry{f::SBGGR12, PixelLayout::Bayer16, BayerOrder::BGGR, 12},
    Entry{f::SRGGB10, PixelLayout::Bayer16, BayerOrder::RGGB, 10},
    Entry{f::SGRBG10, PixelLayout::Bayer16, BayerOrder::GRBG, 10},
    Entry{f::SGBRG10, PixelLayout::Bayer16, BayerOrder::GBRG, 10},
    Entry{f::SBGGR10, PixelLayout::Bayer16, BayerOrder::BGGR, 10},
    Entry{f::SRGGB16, PixelLayout::Bayer16, BayerOrder::RGGB, 16},
    Entry{f::SGRBG16, PixelLayout::Bayer16, BayerOrder::GRBG, 16},
    Entry{f::SGBRG16, PixelLayout::Bayer16, BayerOrder::GBRG, 16},
    Entry{f::SBGGR16, PixelLayout::Bayer16, BayerOrder::BGGR, 16},
    Entry{f::SRGGB8, PixelLayout::Bayer8, BayerOrder::RGGB, 8},
    Entry{f::SGRBG8, PixelLayout::Bayer8, BayerOrder::GRBG, 8},
    Entry{f::SGBRG8, PixelLayout::Bayer8, BayerOrder::GBRG, 8},
    Entry{f::SBGGR8, PixelLayout::Bayer8, BayerOrder::BGGR, 8},
    Entry{f::BGR888, PixelLayout::RGB24, BayerOrder::RGGB, 8},  // bytes R, G, B
    Entry{f::RGB888, PixelLayout::BGR24, BayerOrder::RGGB, 8},  // bytes B, G, R
    Entry{f::YUYV, PixelLayout::YUYV, BayerOrder::RGGB, 8},
};

}  // namespace

std::optional<v4l2::PixelFormat> pixel_layout(const libcamera::PixelFormat& format) {
  for (const Entry& e : kEntries) {
    if (e.format == format) {
      v4l2::PixelFormat out;
      out.layout = e.layout;
      out.bayer = e.order;
      out.bits = e.bits;
      return out;
    }
  }
  return std::nullopt;
}

int format_rank(const libcamera::PixelFormat& format) {
  for (std::size_t i = 0; i < kEntries.size(); ++i)
    if (kEntries[i].format == format) return static_cast<int>(i);
  return -1;
}

v4l2::PixelFormat stream_pixel_format(const libcamera::StreamConfiguration& config) {
  v4l2::PixelFormat out = pixel_layout(config.pixelFormat).value_or(v4l2::PixelFormat{});
  out.bytes_per_line = config.stride;
  // Raw Bayer is linear whatever the colour space says; the others follow it.
  if (config.colorSpace) {
    using CS = libcamera::ColorSpace;
    switch (config.colorSpace->transferFunction) {
      case CS::TransferFunction::Linear:
        out.transfer = v4l2::TransferFunction::Linear;
        break;
      case CS::TransferFunction::Rec709:
        out.transfer = v4l2::TransferFunction::Rec709;
        break;
      case CS::TransferFunction::Srgb:
        out.transfer = v4l2::TransferFunction::Srgb;
        break;
    }
    out.encoding = config.colorSpace->ycbcrEncoding == CS::YcbcrEncoding::Rec709
                       ? v4l2::YcbcrEncoding::Bt709
                       : v4l2::YcbcrEncoding::Bt601;
    out.full_range = config.colorSpace->range == CS::Range::Full;
  }
  return out;
}

}  // namespace probeless::libcam
