#pragma once
// CVF on the CPU with OpenCV doing the heavy steps (cv::ximgproc::guidedFilter with the colour
// guide for both filters, cv::dilate for erosion and band): the speed and quality yardstick
// of `probeless bench occlusion`. Same methods and parameters as the CPU references, always
// with the exact (not subsampled) wide filter.
#include "core/image.hpp"
#include "kernels/occlusion/common/cvf_params.hpp"

namespace probeless::eval {

// The thesis's CVF (cvf_reference.hpp).
ImageF cvf_opencv_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                            const ImageF& virtual_depth_mm,
                            const occlusion::CvfParams& params = {});

// The shipped CVF (cvf_local_reference.hpp): the local costs and softness by the plain C++
// of local_costs_reference() (integral images for the prior), the rest as above.
ImageF cvf_local_opencv_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                                  const ImageF& virtual_depth_mm,
                                  const occlusion::CvfLocalParams& params = {});

}  // namespace probeless::eval
