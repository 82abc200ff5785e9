// Radiance RGBE (.hdr / .pic): G. Ward, "Real Pixels" (Graphics Gems II, 1991) and the
// Radiance file format notes. Decoding matches the reference reader rgbe.c (and stb_image,
// OpenCV): value = byte * 2^(exponent - 136), no half-step offset.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>

#include "core/read_limits.hpp"
#include "drivers/io/hdr_image.hpp"

namespace probeless {
namespace {

constexpr std::size_t kMaxHeaderLine = 4096;
// The least a scanline can take in the file: one 4-byte pixel (old-style runs repeat it up to
// 255 << 16 times; a new-style RLE scanline needs more). Checked before allocating.
constexpr std::size_t kMinScanlineBytes = 4;
constexpr int kMinRleWidth = 8, kMaxRleWidth = 0x7fff;

class Cursor {
 public:
  Cursor(std::span<const std::uint8_t> bytes, const std::filesystem::path& name)
      : bytes_(bytes), name_(name) {}

  [[noreturn]] void fail(const std::string& what) const { throw ImageFileError(name_, what); }

  bool at_end() const { return pos_ >= bytes_.size(); }
  std::size_t left() const { return bytes_.size() - pos_; }
  std::uint8_t peek(std::size_t ahead) const { return bytes_[pos_ + ahead]; }
  std::uint8_t byte(int row) {
    if (at_end()) fail("truncated: pixel data ends in row " + std::to_string(row));
    return bytes_[pos_++];
  }
  // A header line without its '\n' (or "\r\n").
  std::string_view line() {
    const auto* begin = reinterpret_cast<const char*>(bytes_.data()) + pos_;
    const std::string_view rest(begin, std::min(left(), kMaxHeaderLine));
    const auto eol = rest.find('\n');
    if (eol == std::string_view::npos)
      fail("truncated header (a line without an end, or longer than 4096 bytes)");
    pos_ += eol + 1;
    std::string_view l = rest.substr(0, eol);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    return l;
  }

 private:
  std::span<const std::uint8_t> bytes_;
  const std::filesystem::path& name_;
  std::size_t pos_ = 0;
};

struct Header {
  int width = 0, height = 0;
  bool bottom_up = false;  // "+Y": the first scanline is the bottom row
  double exposure = 1.0;
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

Header read_header(Cursor& in) {
  Header h;
  if (in.left() < 2 || in.peek(0) != '#' || in.peek(1) != '?')
    in.fail("not a Radiance HDR file (no \"#?\" signature)");
  in.line();
  for (;;) {
    const std::string_view l = in.line();
    if (trim(l).empty()) break;
    if (l.starts_with("FORMAT=")) {
      const std::string_view format = trim(l.substr(7));
      if (format != "32-bit_rle_rgbe")
        in.fail("unsupported FORMAT " + std::string(format) + " (only 32-bit_rle_rgbe)");
    } else if (l.starts_with("EXPOSURE=")) {
      // Cumulative: each line is a further multiplier applied to the stored values.
      const std::string_view v = trim(l.substr(9));
      double e = 0;
      const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), e);
      if (ec != std::errc() || end != v.data() + v.size() || !(e > 0) || !std::isfinite(e))
        in.fail("bad EXPOSURE value: " + std::string(v));
      h.exposure *= e;
    }
  }
  // Resolution string: "-Y H +X W" is the usual top-down layout; "+Y H +X W" is bottom-up.
  const std::string_view res = in.line();
  char ya[3] = {}, xa[3] = {};
  long hh = 0, ww = 0;
  const std::string text(res);
  if (std::sscanf(text.c_str(), "%2s %ld %2s %ld", ya, &hh, xa, &ww) != 4 ||
      std::string_view(xa) != "+X" ||
      (std::string_view(ya) != "-Y" && std::string_view(ya) != "+Y"))
    in.fail("unsupported resolution line \"" + text + "\" (expected -Y H +X W or +Y H +X W)");
  if (!read_limits::image_size_ok(ww, hh))
    in.fail("bad image size " + std::to_string(ww) + "x" + std::to_string(hh) +
            " (limits: " + std::to_string(read_limits::kMaxImageSide) + " a side, " +
            std::to_string(read_limits::kMaxImagePixels) + " pixels)");
  if (in.left() < static_cast<std::size_t>(hh) * kMinScanlineBytes)
    in.fail("truncated: " + std::to_string(hh) + " scanlines need at least " +
            std::to_string(static_cast<std::size_t>(hh) * kMinScanlineBytes) + " bytes, " +
            std::to_string(in.left()) + " left");
  h.width = static_cast<int>(ww);
  h.height = static_cast<int>(hh);
  h.bottom_up = std::string_view(ya) == "+Y";
  return h;
}

// One scanline of RGBE quadruples into `out` (4 * width bytes).
void read_scanline(Cursor& in, int width, int row, std::uint8_t* out) {
  const bool rle = width >= kMinRleWidth && width <= kMaxRleWidth && in.left() >= 4 &&
                   in.peek(0) == 2 && in.peek(1) == 2 && !(in.peek(2) & 0x80);
  if (rle) {
    for (int i = 0; i < 2; ++i) in.byte(row);
    const int declared = (in.byte(row) << 8) | in.byte(row);
    if (declared != width)
      in.fail("scanline " + std::to_string(row) + " declares width " + std::to_string(declared));
    // Each of the four components is stored separately, as runs and literal blocks.
    for (int c = 0; c < 4; ++c) {
      for (int x = 0; x < width;) {
        int count = in.byte(row);
        const bool run = count > 128;
        if (run) count -= 128;
        if (count == 0 || x + count > width)
          in.fail("bad run length in scanline " + std::to_string(row));
        if (run) {
          const std::uint8_t v = in.byte(row);
          for (int i = 0; i < count; ++i) out[4 * (x++) + c] = v;
        } else {
          for (int i = 0; i < count; ++i) out[4 * (x++) + c] = in.byte(row);
        }
      }
    }
    return;
  }
  // Flat pixels, with the old run encoding: (1, 1, 1, n) repeats the previous pixel n times,
  // consecutive repeat pixels shifting n by 8 bits each.
  int shift = 0;
  for (int x = 0; x < width;) {
    std::uint8_t p[4];
    for (auto& b : p) b = in.byte(row);
    if (p[0] == 1 && p[1] == 1 && p[2] == 1) {
      if (x == 0 || shift > 16) in.fail("bad old-style run in scanline " + std::to_string(row));
      const long count = static_cast<long>(p[3]) << shift;
      if (x + count > width) in.fail("run past the end of scanline " + std::to_string(row));
      for (long i = 0; i < count; ++i, ++x) std::copy_n(out + 4 * (x - 1), 4, out + 4 * x);
      shift += 8;
    } else {
      std::copy_n(p, 4, out + 4 * (x++));
      shift = 0;
    }
  }
}

void rgbe_to_float(const std::uint8_t* rgbe, float scale, float* rgb) {
  if (rgbe[3] == 0) {
    rgb[0] = rgb[1] = rgb[2] = 0;
    return;
  }
  const float f = std::ldexp(1.0f, rgbe[3] - 136) * scale;
  for (int c = 0; c < 3; ++c) rgb[c] = rgbe[c] * f;
}

void float_to_rgbe(const float* rgb, std::uint8_t* rgbe) {
  float v[3];
  for (int c = 0; c < 3; ++c)  // RGBE holds neither negatives nor NaN; 1e38 is near its top
    v[c] = rgb[c] > 0 ? std::min(rgb[c], 1e38f) : 0.0f;
  const float m = std::max({v[0], v[1], v[2]});
  if (!(m > 1e-32f)) {
    std::fill_n(rgbe, 4, 0);
    return;
  }
  int e = 0;
  const float scale = std::frexp(m, &e) * 256.0f / m;
  for (int c = 0; c < 3; ++c) rgbe[c] = static_cast<std::uint8_t>(std::min(255.0f, v[c] * scale));
  rgbe[3] = static_cast<std::uint8_t>(e + 128);
}

// One component of a scanline as runs (of 3 or more equal bytes) and literal blocks.
void write_component(const std::uint8_t* data, int width, std::vector<std::uint8_t>& out) {
  auto run_at = [&](int x) {
    int n = 1;
    while (x + n < width && n < 127 && data[4 * (x + n)] == data[4 * x]) ++n;
    return n;
  };
  for (int x = 0; x < width;) {
    const int run = run_at(x);
    if (run >= 3) {
      out.push_back(static_cast<std::uint8_t>(128 + run));
      out.push_back(data[4 * x]);
      x += run;
      continue;
    }
    int end = x + run;
    while (end < width && end - x < 128 && run_at(end) < 3) end += run_at(end);
    end = std::min(end, x + 128);
    out.push_back(static_cast<std::uint8_t>(end - x));
    for (; x < end; ++x) out.push_back(data[4 * x]);
  }
}

}  // namespace

ImageRGBF decode_radiance_hdr(std::span<const std::uint8_t> bytes,
                              const std::filesystem::path& name) {
  Cursor in(bytes, name);
  const Header h = read_header(in);
  // EXPOSURE lines multiply: a product that underflows to 0 (or overflows) would give
  // infinite (or zero) radiance everywhere.
  const float scale = static_cast<float>(1.0 / h.exposure);
  if (!std::isfinite(scale) || !(scale >= std::numeric_limits<float>::min())) {
    char product[32];
    std::snprintf(product, sizeof product, "%g", h.exposure);
    in.fail(std::string("EXPOSURE values multiply to ") + product +
            ", out of range (the radiance would be " + (std::isinf(scale) ? "infinite)" : "zero)"));
  }
  ImageRGBF image(h.width, h.height);
  std::vector<std::uint8_t> scanline(4 * static_cast<std::size_t>(h.width));
  for (int i = 0; i < h.height; ++i) {
    read_scanline(in, h.width, i, scanline.data());
    float* row = image.row(h.bottom_up ? h.height - 1 - i : i);
    for (int x = 0; x < h.width; ++x) rgbe_to_float(&scanline[4 * x], scale, row + 3 * x);
  }
  return image;
}

std::vector<std::uint8_t> encode_radiance_hdr(const ImageRGBF& image) {
  const std::string header = "#?RADIANCE\n# written by probeless\nFORMAT=32-bit_rle_rgbe\n\n-Y " +
                             std::to_string(image.height()) + " +X " +
                             std::to_string(image.width()) + "\n";
  std::vector<std::uint8_t> out(header.begin(), header.end());
  const int w = image.width();
  std::vector<std::uint8_t> scanline(4 * static_cast<std::size_t>(w));
  const bool rle = w >= kMinRleWidth && w <= kMaxRleWidth;
  for (int y = 0; y < image.height(); ++y) {
    const float* row = image.row(y);
    for (int x = 0; x < w; ++x) float_to_rgbe(row + 3 * x, &scanline[4 * x]);
    if (!rle) {
      out.insert(out.end(), scanline.begin(), scanline.end());
      continue;
    }
    out.insert(out.end(),
               {2, 2, static_cast<std::uint8_t>(w >> 8), static_cast<std::uint8_t>(w & 0xff)});
    for (int c = 0; c < 4; ++c) write_component(scanline.data() + c, w, out);
  }
  return out;
}

}  // namespace probeless
