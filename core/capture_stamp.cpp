#include "core/capture_stamp.hpp"

#include <algorithm>
#include <array>

namespace probeless {

namespace {

constexpr int kGuardBits = 8, kPayloadBits = 40, kCrcBits = 16;
static_assert(kGuardBits + kPayloadBits + kCrcBits ==
              CaptureStampLayout::kColumns * CaptureStampLayout::kRows);
// Four white and four black cells, not a run of either: a flat or striped patch of the
// scene does not pass for it, and it gives the reader both levels to threshold between.
constexpr std::array<bool, kGuardBits> kGuard{true, false, true, true, false, true, false, false};
constexpr std::uint64_t kPayloadMask = (std::uint64_t{1} << kPayloadBits) - 1;
// Guard white minus guard black, in 8-bit luma, below which there is no stamp to read: after
// JPEG q80 and H.264 at 2 Mbit/s the drawn 0 and 255 stay above ~200 apart.
constexpr int kMinContrast = 96;

std::array<bool, CaptureStampLayout::kColumns * CaptureStampLayout::kRows> cells_of(
    std::uint64_t micros) {
  std::array<bool, CaptureStampLayout::kColumns * CaptureStampLayout::kRows> bits{};
  std::copy(kGuard.begin(), kGuard.end(), bits.begin());
  for (int i = 0; i < kPayloadBits; ++i) bits[kGuardBits + i] = (micros >> i) & 1;
  const std::uint16_t crc = capture_stamp_crc(micros);
  for (int i = 0; i < kCrcBits; ++i) bits[kGuardBits + kPayloadBits + i] = (crc >> i) & 1;
  return bits;
}

// Mean luma of the middle half of a cell: its edges carry the codecs' ringing.
int cell_luma(const ImageRGB8& image, const CaptureStampLayout& l, int index) {
  const int cx = l.x0 + (index % CaptureStampLayout::kColumns) * l.cell_px;
  const int cy = l.y0 + (index / CaptureStampLayout::kColumns) * l.cell_px;
  const int q = l.cell_px / 4;
  int sum = 0, n = 0;
  for (int y = cy + q; y < cy + l.cell_px - q; ++y)
    for (int x = cx + q; x < cx + l.cell_px - q; ++x) {
      const std::uint8_t* p = &image.at(x, y);
      sum += (77 * p[0] + 150 * p[1] + 29 * p[2]) >> 8;  // BT.601 luma, what the codecs keep
      ++n;
    }
  return sum / n;
}

}  // namespace

std::uint16_t capture_stamp_crc(std::uint64_t micros) {
  std::uint16_t crc = 0xFFFF;
  for (int byte = 0; byte < kPayloadBits / 8; ++byte) {
    crc ^= static_cast<std::uint16_t>(((micros >> (8 * byte)) & 0xFF) << 8);
    for (int bit = 0; bit < 8; ++bit)
      crc = static_cast<std::uint16_t>((crc & 0x8000) ? (crc << 1) ^ 0x1021 : crc << 1);
  }
  return crc;
}

CaptureStampLayout capture_stamp_layout(int width, int height) {
  CaptureStampLayout l;
  l.cell_px = 8 * std::max(1, height / 480);
  // Two cells from the left and bottom edges (a display's overscan, a player's rounded
  // corners), the first cell on a 16 px boundary so cells do not straddle coding blocks.
  l.x0 = (2 * l.cell_px + 15) / 16 * 16;
  l.y0 = (height - 2 * l.cell_px - l.height()) / 16 * 16;
  if (l.y0 < l.cell_px || l.x0 + l.width() + l.cell_px > width) l.cell_px = 0;
  return l;
}

bool draw_capture_stamp(ImageRGB8& image, TimestampNs capture_ns) {
  const CaptureStampLayout l = capture_stamp_layout(image.width(), image.height());
  if (l.cell_px == 0) return false;
  const auto micros = static_cast<std::uint64_t>(capture_ns / 1000) & kPayloadMask;
  const auto bits = cells_of(micros);
  // A black border of one cell around the code keeps the scene's colours (4:2:0 chroma
  // bleeds 8 px) and edges out of the outer cells.
  const int c = l.cell_px;
  for (int y = l.y0 - c; y < l.y0 + l.height() + c; ++y)
    for (int x = l.x0 - c; x < l.x0 + l.width() + c; ++x) {
      const int col = (x - l.x0) / c, row = (y - l.y0) / c;
      const bool inside = x >= l.x0 && y >= l.y0 && col < CaptureStampLayout::kColumns &&
                          row < CaptureStampLayout::kRows;
      const std::uint8_t v =
          inside && bits[static_cast<std::size_t>(row * CaptureStampLayout::kColumns + col)] ? 255
                                                                                             : 0;
      std::uint8_t* p = &image.at(x, y);
      p[0] = p[1] = p[2] = v;
    }
  return true;
}

StampReading read_capture_stamp(const ImageRGB8& image) {
  StampReading out;
  const CaptureStampLayout l = capture_stamp_layout(image.width(), image.height());
  if (l.cell_px == 0) return out;
  std::array<int, CaptureStampLayout::kColumns * CaptureStampLayout::kRows> luma{};
  for (std::size_t i = 0; i < luma.size(); ++i) luma[i] = cell_luma(image, l, static_cast<int>(i));

  int white_min = 255, black_max = 0;
  for (int i = 0; i < kGuardBits; ++i) {
    if (kGuard[static_cast<std::size_t>(i)])
      white_min = std::min(white_min, luma[static_cast<std::size_t>(i)]);
    else
      black_max = std::max(black_max, luma[static_cast<std::size_t>(i)]);
  }
  if (white_min - black_max < kMinContrast) {
    out.result = white_min < black_max ? StampRead::BadGuard : StampRead::LowContrast;
    return out;
  }
  // A payload cell must lie in the outer quarters of the guard's range: anything between is
  // a cell the codec smeared, and guessing it would let the CRC alone stand between a
  // damaged stamp and a wrong latency.
  const int threshold = (white_min + black_max) / 2;
  const int margin = (white_min - black_max) / 4;
  std::uint64_t payload = 0;
  std::uint16_t crc = 0;
  for (int i = kGuardBits; i < kGuardBits + kPayloadBits + kCrcBits; ++i) {
    const int v = luma[static_cast<std::size_t>(i)];
    if (v > threshold - margin && v < threshold + margin) {
      out.result = StampRead::Ambiguous;
      return out;
    }
    const std::uint64_t bit = v >= threshold ? 1 : 0;
    if (i < kGuardBits + kPayloadBits)
      payload |= bit << (i - kGuardBits);
    else
      crc = static_cast<std::uint16_t>(crc | bit << (i - kGuardBits - kPayloadBits));
  }
  if (crc != capture_stamp_crc(payload)) {
    out.result = StampRead::BadChecksum;
    return out;
  }
  out.result = StampRead::Ok;
  out.micros = payload;
  return out;
}

TimestampNs unwrap_stamp(std::uint64_t micros, TimestampNs reference_ns) {
  constexpr std::int64_t kSpan = std::int64_t{1} << kPayloadBits;
  const std::int64_t ref_us = reference_ns / 1000;
  // The reference's residue minus the stamp's, folded into [-span/2, span/2).
  std::int64_t behind = (ref_us - static_cast<std::int64_t>(micros & kPayloadMask)) % kSpan;
  if (behind < 0) behind += kSpan;
  if (behind >= kSpan / 2) behind -= kSpan;
  return (ref_us - behind) * 1000;
}

const char* to_string(StampRead r) {
  switch (r) {
    case StampRead::Ok:
      return "ok";
    case StampRead::TooSmall:
      return "too small";
    case StampRead::LowContrast:
      return "low contrast";
    case StampRead::BadGuard:
      return "bad guard";
    case StampRead::Ambiguous:
      return "ambiguous cell";
    case StampRead::BadChecksum:
      return "bad checksum";
  }
  return "?";
}

}  // namespace probeless
