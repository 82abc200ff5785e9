#pragma once
// Direct occlusion: the raw per-pixel depth test, no filtering (thesis 3.4's baselines).
// Direct1 treats unknown real depth as occluding, Direct2 as not.
#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless::occlusion {

enum class UnknownDepth { Occluded, Visible };

class DirectMatte final : public OcclusionMethod {
 public:
  DirectMatte(ComputeContext& ctx, UnknownDepth unknown);
  std::string name() const override;  // "direct1" (Occluded) or "direct2" (Visible)
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) override;

 private:
  ComputeContext& ctx_;
  UnknownDepth unknown_;
  ::cl::Kernel kernel_;
};

}  // namespace probeless::occlusion
