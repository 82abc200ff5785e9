#pragma once
// The occlusion methods the evaluator and the benchmark compare, by config name: the device
// methods of kernels/occlusion/method_registry.hpp (the shipped "cvf" and the thesis's
// "cvf_thesis" among them). The CPU references are compared with the device in the tests and
// the ablation experiment (tests/kernels/cvf_local), not here.
#include <memory>
#include <string>
#include <vector>

#include "kernels/occlusion/method_registry.hpp"

namespace probeless::eval {

// In the order of the report: cvf cvf_thesis direct1 direct2 guided bilateral crabb
// arcore_soft meta_soft (occlusion::method_names()).
const std::vector<std::string>& all_method_names();

// The methods' parameters; `categorise` applies to every CVF-family method.
using MethodSettings = occlusion::MethodParams;

// make_method(ctx, name, settings): the registry's; throws std::invalid_argument for an
// unknown name.
using occlusion::make_method;

}  // namespace probeless::eval
