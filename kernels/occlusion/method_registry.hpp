#pragma once
// The occlusion methods that run on the device, by config name ([occlusion] method,
// docs/occlusion.md): what the service chooses from and the evaluator builds on.
#include <memory>
#include <string>
#include <vector>

#include "kernels/occlusion/common/cvf_params.hpp"
#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless::occlusion {

// In the order of the evaluator's report: cvf cvf_thesis direct1 direct2 guided bilateral
// crabb arcore_soft meta_soft.
const std::vector<std::string>& method_names();

struct MethodParams {
  // The depth test and erosion of every method built on CVF's categories (cvf, cvf_thesis,
  // guided, bilateral): one place for a protocol to change them (the matting protocol's exact
  // trimap needs no erosion).
  CategoriseParams categorise;
  CvfLocalParams cvf;    // "cvf", the shipped CVF (its categorise is replaced by the above)
  CvfParams cvf_thesis;  // "cvf_thesis"; its wide filter's radius and eps are guided's
};

// Throws std::invalid_argument for a name not in method_names().
std::unique_ptr<OcclusionMethod> make_method(ComputeContext& ctx, const std::string& name,
                                             const MethodParams& params = {});

}  // namespace probeless::occlusion
