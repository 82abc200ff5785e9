#pragma once
// JPEG through libjpeg-turbo's TurboJPEG API (SIMD on x86-64 and arm64). The encoder owns
// its handle and an output buffer sized once for the largest JPEG of the image size, so a
// steady stream of frames allocates nothing. One encoder per thread: a TurboJPEG handle is
// not thread-safe.
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/image.hpp"

namespace probeless {

struct JpegError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class JpegEncoder {
 public:
  // 80: the mjpg-streamer/ustreamer default, about 40-60 KB for a 640x480 scene.
  explicit JpegEncoder(int quality = 80);
  ~JpegEncoder();
  JpegEncoder(const JpegEncoder&) = delete;
  JpegEncoder& operator=(const JpegEncoder&) = delete;
  JpegEncoder(JpegEncoder&& other) noexcept;
  JpegEncoder& operator=(JpegEncoder&& other) noexcept;

  int quality() const { return quality_; }
  void set_quality(int quality);  // 1..100

  // Colour is 4:2:0 subsampled (what every browser and player expects of MJPEG); gray is
  // written as a one-channel JPEG. The bytes stay valid until the next encode().
  std::span<const std::uint8_t> encode(const ImageRGB8& image);
  std::span<const std::uint8_t> encode(const ImageGray8& image);

  // The same, copied out once for sharing between readers (the HTTP clients).
  std::shared_ptr<const std::vector<std::uint8_t>> encode_shared(const ImageRGB8& image);

 private:
  std::span<const std::uint8_t> encode_raw(const std::uint8_t* pixels, int width, int height,
                                           int pixel_format, int subsampling);

  void* handle_ = nullptr;  // tjhandle
  int quality_;
  std::unique_ptr<std::uint8_t[]> buffer_;
  std::size_t capacity_ = 0;
};

class JpegDecoder {
 public:
  JpegDecoder();
  ~JpegDecoder();
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;
  JpegDecoder(JpegDecoder&&) = delete;
  JpegDecoder& operator=(JpegDecoder&&) = delete;

  // Strict: a warning (truncated or corrupt data) is an error too.
  ImageRGB8 decode(std::span<const std::uint8_t> jpeg);

 private:
  void* handle_ = nullptr;
};

}  // namespace probeless
