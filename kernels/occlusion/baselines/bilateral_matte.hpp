#pragma once
// The "Bilateral" baseline on the device (bilateral_matte_reference.hpp is its CPU twin).
#include "kernels/occlusion/baselines/bilateral_matte_reference.hpp"
#include "kernels/occlusion/common/categorise.hpp"

namespace probeless::occlusion {

class BilateralMatte final : public OcclusionMethod {
 public:
  BilateralMatte(ComputeContext& ctx, const BilateralMatteParams& params = {});
  std::string name() const override { return "bilateral"; }
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) override;

 private:
  ComputeContext& ctx_;
  BilateralMatteParams params_;
  Categoriser categoriser_;
  ::cl::Kernel kernel_;
};

}  // namespace probeless::occlusion
