#include "kernels/occlusion/cvf/histogram_reference.hpp"

#include <numeric>
#include <stdexcept>

namespace probeless::occlusion {

std::uint32_t ColourModels::infront_total() const {
  return std::accumulate(infront.begin(), infront.end(), std::uint32_t{0});
}
std::uint32_t ColourModels::behind_total() const {
  return std::accumulate(behind.begin(), behind.end(), std::uint32_t{0});
}

ColourModels colour_histograms_reference(const ImageRGB8& colour, const CategoryImage& categories,
                                         const ImageGray8& band, int bins_per_channel) {
  if (bins_per_channel < 1 || bins_per_channel > 16)
    throw std::invalid_argument("colour histograms: bins per channel must be 1..16");
  const std::size_t bins =
      static_cast<std::size_t>(bins_per_channel) * bins_per_channel * bins_per_channel;
  ColourModels m{bins_per_channel, std::vector<std::uint32_t>(bins, 0),
                 std::vector<std::uint32_t>(bins, 0)};
  for (int y = 0; y < colour.height(); ++y)
    for (int x = 0; x < colour.width(); ++x) {
      if (!band.at(x, y)) continue;
      const auto c = static_cast<Category>(categories.at(x, y));
      if (c != Category::Infront && c != Category::Behind) continue;
      const int bin =
          colour_bin(colour.at(x, y, 0), colour.at(x, y, 1), colour.at(x, y, 2), bins_per_channel);
      (c == Category::Infront ? m.infront : m.behind)[bin]++;
    }
  return m;
}

}  // namespace probeless::occlusion
