#pragma once
// The occlusion methods the evaluator and the benchmark compare, by config name: the device
// methods of kernels/occlusion/method_registry.hpp and the evaluation-only ones.
#include <memory>
#include <string>
#include <vector>

#include "kernels/occlusion/common/cvf_params.hpp"
#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/occlusion/cvf/cvf_local_reference.hpp"

namespace probeless::eval {

// In the order of the report: cvf direct1 direct2 guided bilateral crabb arcore_soft meta_soft
// (occlusion::method_names()).
const std::vector<std::string>& all_method_names();

struct MethodSettings {
  occlusion::CvfParams cvf;  // its categorise params are shared by guided and bilateral
  // "cvf_local": the proposed CVF change, evaluation only (not in all_method_names()): its CPU
  // reference run on the host (docs/occlusion.md "Local colour models"). Takes the categorise
  // params of `cvf` so both protocols treat it like the other methods.
  occlusion::CvfLocalParams cvf_local;
};

// Throws std::invalid_argument for an unknown name.
std::unique_ptr<occlusion::OcclusionMethod> make_method(ComputeContext& ctx,
                                                        const std::string& name,
                                                        const MethodSettings& settings = {});

}  // namespace probeless::eval
