#pragma once
// The "Guided" baseline on the device (guided_matte_reference.hpp is its CPU twin).
#include "kernels/occlusion/baselines/guided_matte_reference.hpp"
#include "kernels/occlusion/common/categorise.hpp"
#include "kernels/occlusion/common/guided_filter.hpp"

namespace probeless::occlusion {

class GuidedMatte final : public OcclusionMethod {
 public:
  GuidedMatte(ComputeContext& ctx, const GuidedMatteParams& params = {});
  std::string name() const override { return "guided"; }
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) override;

 private:
  ComputeContext& ctx_;
  Categoriser categoriser_;
  GuidedFilter filter_;
  ::cl::Kernel pack_;
  DeviceImageF4 packed_, ab_;
};

}  // namespace probeless::occlusion
