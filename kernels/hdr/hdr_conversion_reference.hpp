#pragma once
// CPU reference of the HDR conversion (kernels/hdr/hdr_conversion.cl), plain loops, the same
// float operations in the same order so the kernel matches it exactly.
#include <array>
#include <cstdint>

#include "core/exposure.hpp"
#include "core/image.hpp"
#include "kernels/hdr/hdr_conversion.hpp"

namespace probeless {

using ImageRGBAF = Image<float, 4>;  // rgb radiance up to a constant, a = quality

// One pixel at (x, y): rgb radiance and quality (0 = never use), as convert() documents.
std::array<float, 4> hdr_convert_pixel(const std::uint16_t* rgb, int x, int y,
                                       std::uint16_t black_level, const HdrConversionConstants& c);

ImageRGBAF hdr_conversion_reference(const ImageRGB16& raw, int bit_depth, std::uint16_t black_level,
                                    const Exposure& exposure,
                                    const HdrConversionParams& params = {});

}  // namespace probeless
