#pragma once
// Dense, row-major, interleaved images. One type for every pixel format the project moves
// around, so that drivers, kernels and outputs agree on layout without conversions.
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

namespace probeless {

template <typename T, int Channels>
class Image {
 public:
  using value_type = T;
  static constexpr int channels = Channels;

  Image() = default;
  Image(int width, int height, T fill = T{}) : width_(width), height_(height) {
    if (width < 0 || height < 0) throw std::invalid_argument("Image: negative size");
    data_.assign(static_cast<std::size_t>(width) * height * Channels, fill);
  }
  // A moved-from image is empty (0x0), not a size without pixels: code that reuses an image
  // when its size already matches (the sources' read(frame)) must not write into nothing.
  Image(const Image&) = default;
  Image& operator=(const Image&) = default;
  Image(Image&& other) noexcept
      : width_(std::exchange(other.width_, 0)),
        height_(std::exchange(other.height_, 0)),
        data_(std::move(other.data_)) {
    other.data_.clear();
  }
  Image& operator=(Image&& other) noexcept {
    if (this != &other) {
      width_ = std::exchange(other.width_, 0);
      height_ = std::exchange(other.height_, 0);
      data_ = std::move(other.data_);
      other.data_.clear();
    }
    return *this;
  }

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return data_.empty(); }
  std::size_t pixel_count() const { return static_cast<std::size_t>(width_) * height_; }
  // Elements per row (no padding: rows are contiguous).
  std::size_t row_elements() const { return static_cast<std::size_t>(width_) * Channels; }
  std::size_t size_bytes() const { return data_.size() * sizeof(T); }

  T* data() { return data_.data(); }
  const T* data() const { return data_.data(); }
  std::span<T> elements() { return data_; }
  std::span<const T> elements() const { return data_; }

  T* row(int y) { return data_.data() + static_cast<std::size_t>(y) * row_elements(); }
  const T* row(int y) const { return data_.data() + static_cast<std::size_t>(y) * row_elements(); }
  T& at(int x, int y, int c = 0) { return row(y)[static_cast<std::size_t>(x) * Channels + c]; }
  const T& at(int x, int y, int c = 0) const {
    return row(y)[static_cast<std::size_t>(x) * Channels + c];
  }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }

  bool operator==(const Image&) const = default;

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<T> data_;
};

using ImageRGB8 = Image<std::uint8_t, 3>;    // display-referred colour, sRGB-ish gamma 2.2
using ImageGray8 = Image<std::uint8_t, 1>;   // masks (0 / 255) and 8-bit mattes
using ImageRGBA8 = Image<std::uint8_t, 4>;   // rendered virtual colour with coverage
using DepthImage = Image<std::uint16_t, 1>;  // millimetres, 0 = unknown
using ImageRGB16 = Image<std::uint16_t, 3>;  // linear raw sensor values (8..16 bit)
using ImageF = Image<float, 1>;              // mattes (alpha in [0,1]), costs, linear depth
using ImageRGBF = Image<float, 3>;           // linear HDR radiance, up to a constant

}  // namespace probeless
