#pragma once
// CVF's depth test on the device (cvf_categorise.cl): categories with eroded infront/behind
// borders, and the separable dilation the band uses. Shared by CVF, Guided and Bilateral.
#include "kernels/occlusion/common/cvf_params.hpp"
#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless::occlusion {

class Categoriser {
 public:
  Categoriser(ComputeContext& ctx, const CategoriseParams& params);
  // Writes categories() (Category values) and process_mask() (1 on process pixels).
  void run(const OcclusionInputs& in);
  // dst = OR of src over the clipped (2r+1)^2 window.
  void dilate(const DeviceImageGray8& src, DeviceImageGray8& dst, int radius);

  const DeviceImageGray8& categories() const { return categories_; }
  const DeviceImageGray8& process_mask() const { return process_; }

 private:
  ComputeContext& ctx_;
  CategoriseParams params_;
  ::cl::Kernel raw_bits_, dilate_rows_, dilate_cols_, erode_;
  DeviceImageGray8 raw_, tmp_, near_, categories_, process_;
};

}  // namespace probeless::occlusion
