#pragma once
// Scores of an occlusion matte against ground truth (thesis 3.5): mean squared error over the
// evaluated pixels (eq. 3.1), the same in a band around the true silhouettes, the sum of
// absolute differences (alphamatting.com), and temporal noise across the frames of a static
// scene. Pure functions on images; docs/occlusion.md "Metrics" has the definitions.
#include <optional>
#include <vector>

#include "core/image.hpp"

namespace probeless::eval {

// Mean of (alpha - truth)^2 over pixels where mask != 0; nullopt when there are none.
std::optional<double> matte_mse(const ImageF& alpha, const ImageF& truth, const ImageGray8& mask);

// Sum of |alpha - truth| over pixels where mask != 0, divided by 1000 (alphamatting.com's unit).
double matte_sad(const ImageF& alpha, const ImageF& truth, const ImageGray8& mask);

// 255 on pixels of `mask` within `radius` (Chebyshev distance) of a true silhouette: a pixel
// whose truth differs by >= 0.5 from a 4-neighbour's, both in `mask`.
ImageGray8 silhouette_band(const ImageF& truth, const ImageGray8& mask, int radius);

// Mean over pixels in every frame's mask of the per-pixel variance (population, divide by K)
// across frames of alpha - truth. For a static scene the truth is constant and this is the
// variance of the matte itself. nullopt with fewer than two frames or no common pixel.
std::optional<double> temporal_noise(const std::vector<ImageF>& alphas,
                                     const std::vector<ImageF>& truths,
                                     const std::vector<ImageGray8>& masks);

}  // namespace probeless::eval
