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

// In the order of the evaluator's report: cvf direct1 direct2 guided bilateral crabb
// arcore_soft meta_soft.
const std::vector<std::string>& method_names();

// `cvf`: CVF's parameters; its categorise params are shared by guided and bilateral, its wide
// filter is guided's. Throws std::invalid_argument for a name not in method_names().
std::unique_ptr<OcclusionMethod> make_method(ComputeContext& ctx, const std::string& name,
                                             const CvfParams& cvf = {});

}  // namespace probeless::occlusion
