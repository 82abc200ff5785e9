#pragma once
// CPU reference of CVF's colour models (thesis 3.3.2): joint RGB histograms of the infront
// and behind pixels inside the band around the process region.
#include <cstdint>
#include <vector>

#include "core/image.hpp"
#include "kernels/occlusion/common/cvf_params.hpp"

namespace probeless::occlusion {

struct ColourModels {
  int bins_per_channel = 4;
  std::vector<std::uint32_t> infront;  // bins_per_channel^3 counts
  std::vector<std::uint32_t> behind;
  std::uint32_t infront_total() const;
  std::uint32_t behind_total() const;
};

ColourModels colour_histograms_reference(const ImageRGB8& colour, const CategoryImage& categories,
                                         const ImageGray8& band, int bins_per_channel);

}  // namespace probeless::occlusion
