#pragma once
// CPU reference of cost-volume-filtering occlusion (thesis ch. 3): the whole method in plain
// C++, every intermediate kept, for the tests of the OpenCL stage and for the evaluator.
#include "core/image.hpp"
#include "kernels/occlusion/common/cvf_params.hpp"
#include "kernels/occlusion/cvf/histogram_reference.hpp"

namespace probeless::occlusion {

struct CvfTrace {
  CategoryImage categories;
  ImageGray8 band;
  ColourModels models;
  bool colour_models_valid = false;  // both classes had >= min_samples pixels in the band
  ImageF cost;                       // probability that the real surface hides the object
  ImageF wide;                       // cost after the wide guided filter
  ImageF mask;                       // 1 = hidden: infront 1, behind 0, else wide > 0.5
  ImageF feather;                    // mask after the narrow guided filter
  ImageF alpha;                      // visibility of the virtual object, 0 off it
};

// Cost of one pixel (thesis 3.3.3). With valid colour models a process pixel costs
// P(c | infront) / (P(c | infront) + P(c | behind)) (0.5 when both are 0); without them the
// depth test decides: 1 when real < virtual, 0 when real >= virtual, 0.5 when unknown.
float cvf_cost(Category c, int bin, const ColourModels& models, bool models_valid,
               std::uint16_t real_mm, float virtual_mm);

CvfTrace cvf_reference(const ImageRGB8& colour, const DepthImage& real_depth_mm,
                       const ImageF& virtual_depth_mm, const CvfParams& params = {});

// The last steps, shared with the baselines' references: alpha = 1 - filtered cost on the
// object (clamped to [0, 1]), 0 off it.
ImageF visibility_from_cost(const ImageF& filtered_cost, const ImageF& virtual_depth_mm);

}  // namespace probeless::occlusion
