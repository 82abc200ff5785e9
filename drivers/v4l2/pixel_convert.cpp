#include "drivers/v4l2/pixel_convert.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace probeless::v4l2 {
namespace {

constexpr int kLinearMax = 4095;  // gamma-coded formats are linearised into 12 bit

// 0 = red, 1 = green, 2 = blue of the Bayer sample at (x, y).
int bayer_channel(BayerOrder order, int x, int y) {
  static constexpr std::array<std::array<int, 4>, 4> tiles = {{
      {0, 1, 1, 2},  // RGGB: (0,0) (1,0) (0,1) (1,1)
      {2, 1, 1, 0},  // BGGR
      {1, 0, 2, 1},  // GRBG
      {1, 2, 0, 1},  // GBRG
  }};
  return tiles[static_cast<std::size_t>(order)][static_cast<std::size_t>((y & 1) * 2 + (x & 1))];
}

int bytes_per_pixel(PixelLayout layout) {
  switch (layout) {
    case PixelLayout::Bayer8:
      return 1;
    case PixelLayout::Bayer16:
      return 2;
    case PixelLayout::RGB24:
    case PixelLayout::BGR24:
      return 3;
    case PixelLayout::YUYV:
      return 2;
  }
  return 1;
}

// Bilinear demosaic: each channel of a pixel is its own sample where the pattern has that
// colour there, else the mean of that colour's samples in the 3x3 neighbourhood (clamped at
// the border). On a Bayer tile this is exactly the classic bilinear kernel (4 crosses for G,
// 2 or 4 neighbours for R/B), and it keeps values linear.
template <typename SampleAt>
void demosaic(int width, int height, BayerOrder order, SampleAt sample, ImageRGB16& out) {
  for (int y = 0; y < height; ++y) {
    std::uint16_t* o = out.row(y);
    for (int x = 0; x < width; ++x, o += 3) {
      std::array<std::uint32_t, 3> sum{};
      std::array<std::uint32_t, 3> count{};
      for (int dy = -1; dy <= 1; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= height) continue;
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx;
          if (xx < 0 || xx >= width) continue;
          const int c = bayer_channel(order, xx, yy);
          sum[static_cast<std::size_t>(c)] += sample(xx, yy);
          ++count[static_cast<std::size_t>(c)];
        }
      }
      const int own = bayer_channel(order, x, y);
      for (int c = 0; c < 3; ++c) {
        const auto ci = static_cast<std::size_t>(c);
        o[c] = c == own ? static_cast<std::uint16_t>(sample(x, y))
                        : static_cast<std::uint16_t>((sum[ci] + count[ci] / 2) / count[ci]);
      }
    }
  }
}

std::array<std::uint16_t, 256> linear_table(TransferFunction transfer) {
  std::array<std::uint16_t, 256> t{};
  for (int i = 0; i < 256; ++i) {
    t[static_cast<std::size_t>(i)] = static_cast<std::uint16_t>(
        std::lround(linearise(static_cast<std::uint8_t>(i), transfer) * kLinearMax));
  }
  return t;
}

std::uint8_t to_code(double v) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
}

void convert_yuyv(const std::uint8_t* in, const PixelFormat& f, int width, int height,
                  ImageRGB16& out) {
  const auto table = linear_table(f.transfer);
  // Kr/Kb of the encoding (ITU-R BT.601 / BT.709) give the inverse matrix's coefficients.
  const double kr = f.encoding == YcbcrEncoding::Bt709 ? 0.2126 : 0.299;
  const double kb = f.encoding == YcbcrEncoding::Bt709 ? 0.0722 : 0.114;
  const double kg = 1.0 - kr - kb;
  const double y_off = f.full_range ? 0.0 : 16.0, y_scale = f.full_range ? 255.0 : 219.0;
  const double c_scale = f.full_range ? 255.0 : 224.0;
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* p = in + static_cast<std::size_t>(y) * f.bytes_per_line;
    std::uint16_t* o = out.row(y);
    for (int x = 0; x < width; x += 2, p += 4) {
      const double cb = (p[1] - 128.0) / c_scale, cr = (p[3] - 128.0) / c_scale;
      const double r_off = 2.0 * (1.0 - kr) * cr;
      const double b_off = 2.0 * (1.0 - kb) * cb;
      const double g_off = -(kr * r_off + kb * b_off) / kg;
      for (int i = 0; i < 2; ++i, o += 3) {
        const double luma = (p[2 * i] - y_off) / y_scale;
        o[0] = table[to_code(luma + r_off)];
        o[1] = table[to_code(luma + g_off)];
        o[2] = table[to_code(luma + b_off)];
      }
    }
  }
}

void convert_rgb(const std::uint8_t* in, const PixelFormat& f, int width, int height,
                 ImageRGB16& out) {
  const auto table = linear_table(f.transfer);
  const bool bgr = f.layout == PixelLayout::BGR24;
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* p = in + static_cast<std::size_t>(y) * f.bytes_per_line;
    std::uint16_t* o = out.row(y);
    for (int x = 0; x < width; ++x, p += 3, o += 3) {
      o[0] = table[p[bgr ? 2 : 0]];
      o[1] = table[p[1]];
      o[2] = table[p[bgr ? 0 : 2]];
    }
  }
}

}  // namespace

double linearise(std::uint8_t code, TransferFunction transfer) {
  const double v = code / 255.0;
  switch (transfer) {
    case TransferFunction::Linear:
      return v;
    case TransferFunction::Srgb:  // IEC 61966-2-1
      return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    case TransferFunction::Rec709:  // inverse of the BT.709 OETF
      return v < 0.081 ? v / 4.5 : std::pow((v + 0.099) / 1.099, 1.0 / 0.45);
  }
  return v;
}

int output_bit_depth(const PixelFormat& format) {
  return format.layout == PixelLayout::Bayer8 ? 8 : 12;
}

std::size_t frame_bytes(const PixelFormat& format, int height) {
  return format.bytes_per_line * static_cast<std::size_t>(height);
}

void convert_to_linear_rgb16(std::span<const std::uint8_t> in, const PixelFormat& f, int width,
                             int height, ImageRGB16& out) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("v4l2 convert: empty frame");
  if (f.bytes_per_line < static_cast<std::size_t>(width) * bytes_per_pixel(f.layout) ||
      in.size() < frame_bytes(f, height)) {
    throw std::invalid_argument(
        fmt::format("v4l2 convert: {} bytes are short of a {}x{} frame", in.size(), width, height));
  }
  const bool pairs = f.layout == PixelLayout::YUYV || f.layout == PixelLayout::Bayer8 ||
                     f.layout == PixelLayout::Bayer16;
  if (pairs && (width % 2 != 0 || (f.layout != PixelLayout::YUYV && height % 2 != 0))) {
    throw std::invalid_argument("v4l2 convert: this format needs an even frame size");
  }
  if (out.width() != width || out.height() != height) out = ImageRGB16(width, height);
  const std::uint8_t* base = in.data();
  const std::size_t stride = f.bytes_per_line;
  switch (f.layout) {
    case PixelLayout::Bayer8:
      demosaic(
          width, height, f.bayer,
          [&](int x, int y) {
            return static_cast<std::uint32_t>(
                base[static_cast<std::size_t>(y) * stride + static_cast<std::size_t>(x)]);
          },
          out);
      return;
    case PixelLayout::Bayer16: {
      // 10- and 12-bit samples move to 12 bit by a power of two (linear); 16 bit drops 4.
      const int shift = 12 - std::clamp(f.bits, 8, 16);
      demosaic(
          width, height, f.bayer,
          [&](int x, int y) {
            const std::uint8_t* p =
                base + static_cast<std::size_t>(y) * stride + 2 * static_cast<std::size_t>(x);
            const std::uint32_t v = static_cast<std::uint32_t>(p[0] | (p[1] << 8));
            return shift >= 0 ? std::min<std::uint32_t>(v << shift, kLinearMax) : v >> -shift;
          },
          out);
      return;
    }
    case PixelLayout::RGB24:
    case PixelLayout::BGR24:
      convert_rgb(base, f, width, height, out);
      return;
    case PixelLayout::YUYV:
      convert_yuyv(base, f, width, height, out);
      return;
  }
}

}  // namespace probeless::v4l2
