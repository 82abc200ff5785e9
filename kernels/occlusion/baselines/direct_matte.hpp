#pragma once
// Direct occlusion: the raw per-pixel depth test, no filtering (thesis 3.4's baselines).
// Direct1 treats unknown real depth as occluding, Direct2 as not.
#include "kernels/occlusion/common/cvf_params.hpp"
#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless::occlusion {

enum class UnknownDepth { Occluded, Visible };

class DirectMatte final : public OcclusionMethod {
 public:
  // `tolerance`: the depth test's (depth_tolerance_mm(); CVF's categories use the same).
  DirectMatte(ComputeContext& ctx, UnknownDepth unknown, const CategoriseParams& tolerance = {});
  std::string name() const override;  // "direct1" (Occluded) or "direct2" (Visible)
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) override;

 private:
  ComputeContext& ctx_;
  UnknownDepth unknown_;
  float tolerance_mm_;
  ::cl::Kernel kernel_;
};

}  // namespace probeless::occlusion
