#include "drivers/v4l2/v4l2_format_map.hpp"

namespace probeless::v4l2 {

std::optional<PixelFormat> layout_of(std::uint32_t fourcc) {
  PixelFormat f;
  auto bayer = [&](PixelLayout layout, BayerOrder order, int bits) {
    f.layout = layout;
    f.bayer = order;
    f.bits = bits;
    return f;
  };
  switch (fourcc) {
    case V4L2_PIX_FMT_SRGGB8:
      return bayer(PixelLayout::Bayer8, BayerOrder::RGGB, 8);
    case V4L2_PIX_FMT_SBGGR8:
      return bayer(PixelLayout::Bayer8, BayerOrder::BGGR, 8);
    case V4L2_PIX_FMT_SGRBG8:
      return bayer(PixelLayout::Bayer8, BayerOrder::GRBG, 8);
    case V4L2_PIX_FMT_SGBRG8:
      return bayer(PixelLayout::Bayer8, BayerOrder::GBRG, 8);
    case V4L2_PIX_FMT_SRGGB10:
      return bayer(PixelLayout::Bayer16, BayerOrder::RGGB, 10);
    case V4L2_PIX_FMT_SBGGR10:
      return bayer(PixelLayout::Bayer16, BayerOrder::BGGR, 10);
    case V4L2_PIX_FMT_SGRBG10:
      return bayer(PixelLayout::Bayer16, BayerOrder::GRBG, 10);
    case V4L2_PIX_FMT_SGBRG10:
      return bayer(PixelLayout::Bayer16, BayerOrder::GBRG, 10);
    case V4L2_PIX_FMT_SRGGB12:
      return bayer(PixelLayout::Bayer16, BayerOrder::RGGB, 12);
    case V4L2_PIX_FMT_SBGGR12:
      return bayer(PixelLayout::Bayer16, BayerOrder::BGGR, 12);
    case V4L2_PIX_FMT_SGRBG12:
      return bayer(PixelLayout::Bayer16, BayerOrder::GRBG, 12);
    case V4L2_PIX_FMT_SGBRG12:
      return bayer(PixelLayout::Bayer16, BayerOrder::GBRG, 12);
    case V4L2_PIX_FMT_SRGGB16:
      return bayer(PixelLayout::Bayer16, BayerOrder::RGGB, 16);
    case V4L2_PIX_FMT_SBGGR16:
      return bayer(PixelLayout::Bayer16, BayerOrder::BGGR, 16);
    case V4L2_PIX_FMT_SGRBG16:
      return bayer(PixelLayout::Bayer16, BayerOrder::GRBG, 16);
    case V4L2_PIX_FMT_SGBRG16:
      return bayer(PixelLayout::Bayer16, BayerOrder::GBRG, 16);
    case V4L2_PIX_FMT_RGB24:
      f.layout = PixelLayout::RGB24;
      return f;
    case V4L2_PIX_FMT_BGR24:
      f.layout = PixelLayout::BGR24;
      return f;
    case V4L2_PIX_FMT_YUYV:
      f.layout = PixelLayout::YUYV;
      return f;
    default:
      return std::nullopt;
  }
}

int preference(const PixelFormat& format) {
  switch (format.layout) {
    case PixelLayout::Bayer16:
      return format.bits == 12 ? 0 : format.bits == 10 ? 1 : 2;
    case PixelLayout::Bayer8:
      return 3;
    case PixelLayout::RGB24:
    case PixelLayout::BGR24:
      return 4;
    case PixelLayout::YUYV:
      return 5;
  }
  return 9;
}

void apply_colourimetry(const v4l2_pix_format& pix, PixelFormat& f) {
  f.bytes_per_line = pix.bytesperline;
  switch (pix.xfer_func) {
    case V4L2_XFER_FUNC_SRGB:
      f.transfer = TransferFunction::Srgb;
      break;
    case V4L2_XFER_FUNC_709:
      f.transfer = TransferFunction::Rec709;
      break;
    case V4L2_XFER_FUNC_NONE:
      f.transfer = TransferFunction::Linear;
      break;
    case V4L2_XFER_FUNC_DEFAULT:
      // The default per colorspace: Rec. 709's curve for the video colorspaces, none for raw,
      // sRGB for sRGB/JPEG and (an approximation) the rest.
      if (pix.colorspace == V4L2_COLORSPACE_RAW) {
        f.transfer = TransferFunction::Linear;
      } else if (pix.colorspace == V4L2_COLORSPACE_REC709 ||
                 pix.colorspace == V4L2_COLORSPACE_SMPTE170M ||
                 pix.colorspace == V4L2_COLORSPACE_BT2020 ||
                 pix.colorspace == V4L2_COLORSPACE_470_SYSTEM_M ||
                 pix.colorspace == V4L2_COLORSPACE_470_SYSTEM_BG) {
        f.transfer = TransferFunction::Rec709;
      } else {
        f.transfer = TransferFunction::Srgb;
      }
      break;
    default:
      f.transfer = TransferFunction::Srgb;
      break;  // DCI-P3, SMPTE 2084, ...: approximate
  }
  const auto enc = pix.ycbcr_enc;
  f.encoding = enc == V4L2_YCBCR_ENC_709 || enc == V4L2_YCBCR_ENC_XV709 ||
                       (enc == V4L2_YCBCR_ENC_DEFAULT && pix.colorspace == V4L2_COLORSPACE_REC709)
                   ? YcbcrEncoding::Bt709
                   : YcbcrEncoding::Bt601;
  f.full_range =
      pix.quantization == V4L2_QUANTIZATION_FULL_RANGE ||
      (pix.quantization == V4L2_QUANTIZATION_DEFAULT && pix.colorspace == V4L2_COLORSPACE_JPEG);
}

std::string fourcc_text(std::uint32_t fourcc) {
  std::string s(4, ' ');
  for (int i = 0; i < 4; ++i)
    s[static_cast<std::size_t>(i)] = static_cast<char>((fourcc >> (8 * i)) & 0xff);
  return s;
}

std::uint32_t fourcc_from_text(const std::string& t) {
  return v4l2_fourcc(t.at(0), t.at(1), t.at(2), t.at(3));
}

}  // namespace probeless::v4l2
