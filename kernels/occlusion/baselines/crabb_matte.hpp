#pragma once
// The "Crabb et al." baseline on the device (crabb_matte_reference.hpp is its CPU twin).
#include "kernels/occlusion/common/occlusion_method.hpp"

namespace probeless::occlusion {

class CrabbMatte final : public OcclusionMethod {
 public:
  explicit CrabbMatte(ComputeContext& ctx);
  std::string name() const override { return "crabb"; }
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) override;

 private:
  ComputeContext& ctx_;
  ::cl::Kernel mean_, matte_;
  ::cl::Buffer stats_;
};

}  // namespace probeless::occlusion
