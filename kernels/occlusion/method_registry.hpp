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

// The matting protocol's changes (an exact trimap stands in for a sensor's depth): no erosion
// (there is no lateral depth noise) and no hole cores (the unknown region is the trimap's, not
// a surface nearer than a sensor's range; with them GT04's MSE rose from 49e-3 to 127e-3,
// docs/occlusion.md "Occluders the sensor cannot see").
void use_exact_trimap(MethodParams& params);

// Throws std::invalid_argument for a name not in method_names().
std::unique_ptr<OcclusionMethod> make_method(ComputeContext& ctx, const std::string& name,
                                             const MethodParams& params = {});

}  // namespace probeless::occlusion
