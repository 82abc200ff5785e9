#pragma once
// CPU reference of kernels/composite/compositor.cl, plain loops, bit-exact with the device.
#include <cstdint>

#include "core/image.hpp"

namespace probeless {

// The matte clamped to [0, 1]; NaN counts as 0 (no virtual object).
float composite_weight(float a);
// a * virt + (1 - a) * real + 0.5, truncated: round half up, in this order of operations
// (the kernel disables fma contraction so that it computes the same floats).
std::uint8_t composite_channel(std::uint8_t real, std::uint8_t virt, float alpha);

ImageRGB8 composite_reference(const ImageRGB8& real_rgb, const ImageRGBA8& virtual_rgba,
                              const ImageF& alpha);
ImageGray8 matte8_reference(const ImageF& alpha);  // round(alpha * 255), half up

}  // namespace probeless
