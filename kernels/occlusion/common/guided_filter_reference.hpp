#pragma once
// CPU reference of the guided filter (He, Sun & Tang, ECCV 2010 / TPAMI 2013) with a colour
// guide: per window the 3x3 covariance of the guide, a = (Sigma + eps U)^-1 cov(I, p),
// b = mean(p) - a . mean(I), q = mean(a) . I + mean(b). Windows are (2r+1)^2 squares clipped to
// the image and means divide by the clipped count, as in He's reference code. Box sums use
// integral images in double precision, so the cost is O(N) whatever the radius.
#include <vector>

#include "core/image.hpp"
#include "kernels/occlusion/common/cvf_params.hpp"

namespace probeless::occlusion {

// Mean over the clipped (2r+1)^2 window of each of `channels` planes stored one after another
// (plane c at offset c * width * height).
std::vector<double> box_mean_planes(const std::vector<double>& planes, int width, int height,
                                    int channels, int radius);

// The guided filter of `input` with the colour guide (components in [0, 1]). With
// params.subsample > 1 it is He & Sun's fast guided filter (arXiv 1505.00996): a and b are
// found on the block-averaged guide and input with radius max(1, round(r / s)), their window
// means are upsampled bilinearly and applied to the full-resolution guide.
ImageF guided_filter_reference(const ImageRGBF& guide, const ImageF& input,
                               const GuidedFilterParams& params);

// Colour frame as the filter's guide: 8-bit values / 255.
ImageRGBF guide_from_rgb8(const ImageRGB8& colour);

}  // namespace probeless::occlusion
