#include "kernels/occlusion/common/categorise_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace probeless::occlusion {
namespace {

// OR of `mask` bits over the clipped (2r+1)^2 window, separably.
Image<std::uint8_t, 1> dilate_bits(const Image<std::uint8_t, 1>& mask, int r) {
  const int w = mask.width(), h = mask.height();
  Image<std::uint8_t, 1> tmp(w, h), out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t v = 0;
      for (int k = std::max(0, x - r); k <= std::min(w - 1, x + r); ++k) v |= mask.at(k, y);
      tmp.at(x, y) = v;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t v = 0;
      for (int k = std::max(0, y - r); k <= std::min(h - 1, y + r); ++k) v |= tmp.at(x, k);
      out.at(x, y) = v;
    }
  return out;
}

}  // namespace

Category raw_category(std::uint16_t real_mm, float virtual_mm, float tolerance_mm) {
  if (!(virtual_mm > 0.0F)) return Category::Ignore;
  if (real_mm == 0) return Category::Process;
  const float real = static_cast<float>(real_mm);
  if (std::fabs(real - virtual_mm) <= tolerance_mm) return Category::Process;
  return real < virtual_mm ? Category::Infront : Category::Behind;
}

Category raw_category(std::uint16_t real_mm, float virtual_mm, const CategoriseParams& params) {
  return raw_category(real_mm, virtual_mm, depth_tolerance_mm(params, virtual_mm));
}

std::string depth_tolerance_options(const CategoriseParams& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, " -DTOL_QUAD=%af -DTOL_Z0=%af", double(p.tolerance_per_mm),
                double(p.tolerance_z0_mm));
  return buf;
}

CategoryImage categorise_reference(const DepthImage& real_depth_mm, const ImageF& virtual_depth_mm,
                                   const CategoriseParams& params) {
  const int w = real_depth_mm.width(), h = real_depth_mm.height();
  if (virtual_depth_mm.width() != w || virtual_depth_mm.height() != h)
    throw std::invalid_argument("categorise_reference: real and virtual depth sizes differ");
  CategoryImage raw(w, h);
  Image<std::uint8_t, 1> bits(w, h);  // bit (category - 1) for on-object categories
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Category c = raw_category(real_depth_mm.at(x, y), virtual_depth_mm.at(x, y), params);
      raw.at(x, y) = static_cast<std::uint8_t>(c);
      bits.at(x, y) = c == Category::Ignore ? 0 : static_cast<std::uint8_t>(1U << (int(c) - 1));
    }
  if (params.erosion_px <= 0) return raw;
  const auto near = dilate_bits(bits, params.erosion_px);
  CategoryImage out = raw;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto c = static_cast<Category>(raw.at(x, y));
      if (c != Category::Infront && c != Category::Behind) continue;
      const std::uint8_t own = static_cast<std::uint8_t>(1U << (int(c) - 1));
      // Only the other known class erodes (bits 0 and 1); process pixels do not.
      if ((near.at(x, y) & ~own & 3U) != 0)
        out.at(x, y) = static_cast<std::uint8_t>(Category::Process);
    }
  return out;
}

ImageGray8 process_band_reference(const CategoryImage& categories, int band_px) {
  Image<std::uint8_t, 1> proc(categories.width(), categories.height());
  for (int y = 0; y < categories.height(); ++y)
    for (int x = 0; x < categories.width(); ++x)
      proc.at(x, y) = categories.at(x, y) == static_cast<std::uint8_t>(Category::Process) ? 1 : 0;
  auto band = dilate_bits(proc, std::max(0, band_px));
  for (auto& v : band.elements()) v = v ? 255 : 0;
  return band;
}

}  // namespace probeless::occlusion
