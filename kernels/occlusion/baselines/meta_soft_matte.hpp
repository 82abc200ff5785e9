#pragma once
// The Meta-Quest-style soft occlusion on the device (meta_soft_matte_reference.hpp is its
// CPU twin).
#include "kernels/occlusion/baselines/meta_soft_matte_reference.hpp"
#include "kernels/occlusion/common/occlusion_method.hpp"

namespace probeless::occlusion {

class MetaSoftMatte final : public OcclusionMethod {
 public:
  MetaSoftMatte(ComputeContext& ctx, const MetaSoftParams& params = {});
  std::string name() const override { return "meta_soft"; }
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) override;

 private:
  ComputeContext& ctx_;
  MetaSoftParams params_;
  ::cl::Kernel kernel_;
};

}  // namespace probeless::occlusion
