#include "kernels/composite/composite_reference.hpp"

#include <stdexcept>

namespace probeless {

float composite_weight(float a) {
  return a > 0.0F ? (a < 1.0F ? a : 1.0F) : 0.0F;
}

std::uint8_t composite_channel(std::uint8_t real, std::uint8_t virt, float alpha) {
  const float a = composite_weight(alpha);
  const float c = a * static_cast<float>(virt) + (1.0F - a) * static_cast<float>(real) + 0.5F;
  return static_cast<std::uint8_t>(c < 255.0F ? c : 255.0F);
}

ImageRGB8 composite_reference(const ImageRGB8& real_rgb, const ImageRGBA8& virtual_rgba,
                              const ImageF& alpha) {
  const int w = real_rgb.width(), h = real_rgb.height();
  if (virtual_rgba.width() != w || virtual_rgba.height() != h || alpha.width() != w ||
      alpha.height() != h)
    throw std::invalid_argument("composite_reference: inputs differ in size");
  ImageRGB8 out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        out.at(x, y, c) =
            composite_channel(real_rgb.at(x, y, c), virtual_rgba.at(x, y, c), alpha.at(x, y));
  return out;
}

ImageGray8 matte8_reference(const ImageF& alpha) {
  ImageGray8 out(alpha.width(), alpha.height());
  for (int y = 0; y < alpha.height(); ++y)
    for (int x = 0; x < alpha.width(); ++x)
      out.at(x, y) = static_cast<std::uint8_t>(composite_weight(alpha.at(x, y)) * 255.0F + 0.5F);
  return out;
}

}  // namespace probeless
