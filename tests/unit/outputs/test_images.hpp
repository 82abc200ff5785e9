#pragma once
// Pictures for the output tests: smooth enough that JPEG keeps them close, distinct per
// frame number so that a test can tell frames apart after a round trip.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>

#include "core/image.hpp"

namespace probeless::testing {

inline ImageRGB8 gradient_image(int width, int height, int frame = 0) {
  ImageRGB8 image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      image.at(x, y, 0) = static_cast<std::uint8_t>((x * 255) / std::max(width - 1, 1));
      image.at(x, y, 1) = static_cast<std::uint8_t>((y * 255) / std::max(height - 1, 1));
      image.at(x, y, 2) = static_cast<std::uint8_t>((frame * 37) & 0xFF);
    }
  }
  return image;
}

// Noise compresses badly: large JPEGs that fill socket buffers quickly.
inline ImageRGB8 noise_image(int width, int height, unsigned seed) {
  ImageRGB8 image(width, height);
  std::mt19937 rng(seed);
  for (auto& v : image.elements()) v = static_cast<std::uint8_t>(rng());
  return image;
}

inline double mean_abs_difference(const ImageRGB8& a, const ImageRGB8& b) {
  double sum = 0;
  const auto ea = a.elements(), eb = b.elements();
  for (std::size_t i = 0; i < ea.size(); ++i) sum += std::abs(int(ea[i]) - int(eb[i]));
  return ea.empty() ? 0 : sum / static_cast<double>(ea.size());
}

}  // namespace probeless::testing
