#pragma once
// CVF on the CPU with OpenCV doing the heavy steps (cv::ximgproc::guidedFilter with the colour
// guide for both filters, cv::dilate for erosion and band): the speed and quality yardstick
// of `probeless bench occlusion`. Same method and parameters as cvf_reference.hpp, always
// with the exact (not subsampled) wide filter.
#include "core/image.hpp"
#include "kernels/occlusion/common/cvf_params.hpp"

namespace probeless::eval {

ImageF cvf_opencv_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                            const ImageF& virtual_depth_mm,
                            const occlusion::CvfParams& params = {});

}  // namespace probeless::eval
