#include "kernels/occlusion/method_registry.hpp"

#include <stdexcept>

#include "kernels/occlusion/baselines/bilateral_matte.hpp"
#include "kernels/occlusion/baselines/crabb_matte.hpp"
#include "kernels/occlusion/baselines/direct_matte.hpp"
#include "kernels/occlusion/baselines/guided_matte.hpp"
#include "kernels/occlusion/baselines/meta_soft_matte.hpp"
#include "kernels/occlusion/baselines/soft_ramp_matte.hpp"
#include "kernels/occlusion/cvf/cvf_matte.hpp"

namespace probeless::occlusion {

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = {"cvf",     "cvf_thesis",  "direct1",
                                                 "direct2", "guided",      "bilateral",
                                                 "crabb",   "arcore_soft", "meta_soft"};
  return names;
}

void use_exact_trimap(MethodParams& params) {
  params.categorise.erosion_px = 0;
  params.cvf.hole_core_px = 0;
}

std::unique_ptr<OcclusionMethod> make_method(ComputeContext& ctx, const std::string& name,
                                             const MethodParams& params) {
  CvfParams cvf = params.cvf_thesis;
  cvf.categorise = params.categorise;
  if (name == "cvf") {
    CvfLocalParams p = params.cvf;
    p.cvf.categorise = params.categorise;
    return std::make_unique<CvfMatte>(ctx, p);
  }
  if (name == "cvf_thesis") return std::make_unique<CvfMatte>(ctx, cvf);
  if (name == "direct1")
    return std::make_unique<DirectMatte>(ctx, UnknownDepth::Occluded, params.categorise);
  if (name == "direct2")
    return std::make_unique<DirectMatte>(ctx, UnknownDepth::Visible, params.categorise);
  if (name == "guided") {
    GuidedMatteParams p;
    p.categorise = cvf.categorise;
    p.filter = {cvf.wide.radius, cvf.wide.eps, 1};
    return std::make_unique<GuidedMatte>(ctx, p);
  }
  if (name == "bilateral") {
    BilateralMatteParams p;
    p.categorise = cvf.categorise;
    return std::make_unique<BilateralMatte>(ctx, p);
  }
  if (name == "crabb") return std::make_unique<CrabbMatte>(ctx);
  if (name == "arcore_soft") return std::make_unique<SoftRampMatte>(ctx);
  if (name == "meta_soft") return std::make_unique<MetaSoftMatte>(ctx);
  std::string known;
  for (const auto& n : method_names()) known += " " + n;
  throw std::invalid_argument("unknown occlusion method '" + name + "' (known:" + known + ")");
}

}  // namespace probeless::occlusion
