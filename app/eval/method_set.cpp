#include "app/eval/method_set.hpp"

#include <stdexcept>

#include "kernels/occlusion/bilateral_matte.hpp"
#include "kernels/occlusion/crabb_matte.hpp"
#include "kernels/occlusion/cvf_matte.hpp"
#include "kernels/occlusion/direct_matte.hpp"
#include "kernels/occlusion/guided_matte.hpp"
#include "kernels/occlusion/meta_soft_matte.hpp"
#include "kernels/occlusion/soft_ramp_matte.hpp"

namespace probeless::eval {
using namespace probeless::occlusion;

const std::vector<std::string>& all_method_names() {
  static const std::vector<std::string> names = {
      "cvf", "direct1", "direct2", "guided", "bilateral", "crabb", "arcore_soft", "meta_soft"};
  return names;
}

std::unique_ptr<OcclusionMethod> make_method(ComputeContext& ctx, const std::string& name,
                                             const MethodSettings& settings) {
  const auto& cat = settings.cvf.categorise;
  if (name == "cvf") return std::make_unique<CvfMatte>(ctx, settings.cvf);
  if (name == "direct1") return std::make_unique<DirectMatte>(ctx, UnknownDepth::Occluded);
  if (name == "direct2") return std::make_unique<DirectMatte>(ctx, UnknownDepth::Visible);
  if (name == "guided") {
    GuidedMatteParams p;
    p.categorise = cat;
    p.filter = {settings.cvf.wide.radius, settings.cvf.wide.eps, 1};
    return std::make_unique<GuidedMatte>(ctx, p);
  }
  if (name == "bilateral") {
    BilateralMatteParams p;
    p.categorise = cat;
    return std::make_unique<BilateralMatte>(ctx, p);
  }
  if (name == "crabb") return std::make_unique<CrabbMatte>(ctx);
  if (name == "arcore_soft") return std::make_unique<SoftRampMatte>(ctx);
  if (name == "meta_soft") return std::make_unique<MetaSoftMatte>(ctx);
  std::string known;
  for (const auto& n : all_method_names()) known += " " + n;
  throw std::invalid_argument("unknown occlusion method '" + name + "' (known:" + known + ")");
}

}  // namespace probeless::eval
