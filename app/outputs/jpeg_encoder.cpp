#include "app/outputs/jpeg_encoder.hpp"

#include <turbojpeg.h>

#include <cstring>
#include <utility>

namespace probeless {
namespace {

std::string tj_error(tjhandle handle, const char* what) {
  return std::string("JPEG ") + what + ": " + tjGetErrorStr2(handle);
}

}  // namespace

JpegEncoder::JpegEncoder(int quality) : quality_(quality) {
  set_quality(quality);
  handle_ = tjInitCompress();
  if (handle_ == nullptr)
    throw JpegError(std::string("tjInitCompress: ") + tjGetErrorStr2(nullptr));
}

JpegEncoder::~JpegEncoder() {
  if (handle_ != nullptr) tjDestroy(handle_);
}

JpegEncoder::JpegEncoder(JpegEncoder&& other) noexcept
    : handle_(std::exchange(other.handle_, nullptr)),
      quality_(other.quality_),
      buffer_(std::move(other.buffer_)),
      capacity_(std::exchange(other.capacity_, 0)) {}

JpegEncoder& JpegEncoder::operator=(JpegEncoder&& other) noexcept {
  if (this != &other) {
    if (handle_ != nullptr) tjDestroy(handle_);
    handle_ = std::exchange(other.handle_, nullptr);
    quality_ = other.quality_;
    buffer_ = std::move(other.buffer_);
    capacity_ = std::exchange(other.capacity_, 0);
  }
  return *this;
}

void JpegEncoder::set_quality(int quality) {
  if (quality < 1 || quality > 100) {
    throw std::invalid_argument("JPEG quality must be in 1..100, got " + std::to_string(quality));
  }
  quality_ = quality;
}

std::span<const std::uint8_t> JpegEncoder::encode(const ImageRGB8& image) {
  return encode_raw(image.data(), image.width(), image.height(), TJPF_RGB, TJSAMP_420);
}

std::span<const std::uint8_t> JpegEncoder::encode(const ImageGray8& image) {
  return encode_raw(image.data(), image.width(), image.height(), TJPF_GRAY, TJSAMP_GRAY);
}

std::shared_ptr<const std::vector<std::uint8_t>> JpegEncoder::encode_shared(
    const ImageRGB8& image) {
  const auto bytes = encode(image);
  return std::make_shared<const std::vector<std::uint8_t>>(bytes.begin(), bytes.end());
}

std::span<const std::uint8_t> JpegEncoder::encode_raw(const std::uint8_t* pixels, int width,
                                                      int height, int pixel_format,
                                                      int subsampling) {
  if (handle_ == nullptr) throw JpegError("JPEG encode: moved-from encoder");
  if (width <= 0 || height <= 0) throw JpegError("JPEG encode: empty image");
  // The worst case for this size: with TJFLAG_NOREALLOC TurboJPEG writes into our buffer
  // and never reallocates, so the buffer is allocated once per size, not once per frame.
  const std::size_t needed = tjBufSize(width, height, subsampling);
  if (needed > capacity_) {
    buffer_ = std::make_unique_for_overwrite<std::uint8_t[]>(needed);
    capacity_ = needed;
  }
  unsigned char* out = buffer_.get();
  unsigned long size = capacity_;
  if (tjCompress2(handle_, pixels, width, 0, height, pixel_format, &out, &size, subsampling,
                  quality_, TJFLAG_NOREALLOC) != 0) {
    throw JpegError(tj_error(handle_, "encode"));
  }
  return {buffer_.get(), static_cast<std::size_t>(size)};
}

JpegDecoder::JpegDecoder() {
  handle_ = tjInitDecompress();
  if (handle_ == nullptr) {
    throw JpegError(std::string("tjInitDecompress: ") + tjGetErrorStr2(nullptr));
  }
}

JpegDecoder::~JpegDecoder() {
  if (handle_ != nullptr) tjDestroy(handle_);
}

ImageRGB8 JpegDecoder::decode(std::span<const std::uint8_t> jpeg) {
  if (jpeg.empty()) throw JpegError("JPEG decode: no data");
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(handle_, jpeg.data(), jpeg.size(), &width, &height, &subsampling,
                          &colorspace) != 0) {
    throw JpegError(tj_error(handle_, "header"));
  }
  ImageRGB8 image(width, height);
  if (tjDecompress2(handle_, jpeg.data(), jpeg.size(), image.data(), width, 0, height, TJPF_RGB,
                    TJFLAG_STOPONWARNING) != 0) {
    throw JpegError(tj_error(handle_, "decode"));
  }
  return image;
}

}  // namespace probeless
