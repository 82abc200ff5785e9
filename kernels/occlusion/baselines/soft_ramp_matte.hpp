#pragma once
// The ARCore-style soft ramp on the device (soft_ramp_matte_reference.hpp is its CPU twin).
#include "kernels/occlusion/baselines/soft_ramp_matte_reference.hpp"
#include "kernels/occlusion/common/occlusion_method.hpp"

namespace probeless::occlusion {

class SoftRampMatte final : public OcclusionMethod {
 public:
  SoftRampMatte(ComputeContext& ctx, const SoftRampParams& params = {});
  std::string name() const override { return "arcore_soft"; }
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) override;

 private:
  ComputeContext& ctx_;
  SoftRampParams params_;
  ::cl::Kernel kernel_;
};

}  // namespace probeless::occlusion
