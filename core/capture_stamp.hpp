#pragma once
// The capture stamp: a frame's capture time written into its colour image as large black and
// white cells, so that a receiver at the far end of an output (an MJPEG viewer, an RTSP
// player) can read when the frame was captured and so time the whole path, glass to glass
// (`probeless bench latency`, docs/outputs.md "Glass-to-glass latency"). Pure functions: no
// clock is read here.
//
// Layout: 16 x 4 cells near the bottom-left corner, on a black border one cell wide:
//   row 0:    8 guard cells, 1 0 1 1 0 1 0 0 (white = 1), then payload bits 0..7
//   rows 1-3: payload bits 8..39, then CRC-16 bits 0..15
// The payload is the capture time in microseconds modulo 2^40 (12.7 days); unwrap_stamp()
// puts it back next to a reference time. The guard's known cells set the black/white
// threshold; a cell too near it, a wrong guard or a wrong CRC rejects the whole reading, so
// a damaged stamp is counted as unreadable rather than read as a wrong time.
#include <cstdint>

#include "core/image.hpp"
#include "core/time.hpp"

namespace probeless {

struct CaptureStampLayout {
  static constexpr int kColumns = 16, kRows = 4;
  int cell_px = 8;     // 8 px up to 959 rows, then 8 px per 480 rows
  int x0 = 0, y0 = 0;  // top-left of the first cell, aligned to 16 px (JPEG's MCU, H.264's MB)
  int width() const { return kColumns * cell_px; }
  int height() const { return kRows * cell_px; }
};

// Where the stamp goes in an image of this size; `cell_px == 0` when the image cannot hold
// it (narrower than 152 px or lower than 64 px at 8 px cells).
CaptureStampLayout capture_stamp_layout(int width, int height);

// Writes the stamp of `capture_ns` into `image`; false (and the image untouched) when the
// image is too small for it.
bool draw_capture_stamp(ImageRGB8& image, TimestampNs capture_ns);

enum class StampRead {
  Ok,
  TooSmall,     // no room for a stamp in an image of this size
  LowContrast,  // the guard's white and black cells are not far apart: no stamp there
  BadGuard,     // a guard cell reads the wrong way
  Ambiguous,    // a payload cell is too near the threshold to call
  BadChecksum,  // every cell read, but the CRC does not match
};
const char* to_string(StampRead r);

struct StampReading {
  StampRead result = StampRead::TooSmall;
  std::uint64_t micros = 0;  // the capture time in microseconds modulo 2^40 (result == Ok)
};

// Reads a stamp drawn by draw_capture_stamp() in an image of the same size, after whatever
// lossy coding the image went through.
StampReading read_capture_stamp(const ImageRGB8& image);

// The CLOCK_MONOTONIC time (ns) whose stamp is `micros` and which lies nearest to
// `reference_ns` (a receiver's clock when the frame arrived): within 6.4 days of it.
TimestampNs unwrap_stamp(std::uint64_t micros, TimestampNs reference_ns);

// CRC-16/CCITT-FALSE (polynomial 0x1021, initial 0xFFFF) of the payload's five bytes.
std::uint16_t capture_stamp_crc(std::uint64_t micros);

}  // namespace probeless
