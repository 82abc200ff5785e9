#include "lab/eval/method_set.hpp"

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

namespace {

// The proposed CVF change as an evaluation-only method: downloads the inputs, runs the CPU
// reference and uploads alpha (milliseconds to seconds per frame; never for the service).
class CvfLocalHostMethod final : public OcclusionMethod {
 public:
  CvfLocalHostMethod(ComputeContext& ctx, const CvfLocalParams& params)
      : ctx_(ctx), params_(params) {}
  std::string name() const override { return "cvf_local"; }
  void process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) override {
    check_inputs(in, name());
    auto& q = ctx_.queue();
    const auto trace = cvf_local_reference(in.color->download(q), in.real_depth_mm->download(q),
                                           in.virtual_depth_mm->download(q), params_);
    alpha.upload(q, trace.alpha);
  }

 private:
  ComputeContext& ctx_;
  CvfLocalParams params_;
};

}  // namespace

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
  if (name == "cvf_local") {
    CvfLocalParams p = settings.cvf_local;
    p.cvf.categorise = cat;
    return std::make_unique<CvfLocalHostMethod>(ctx, p);
  }
  if (name == "crabb") return std::make_unique<CrabbMatte>(ctx);
  if (name == "arcore_soft") return std::make_unique<SoftRampMatte>(ctx);
  if (name == "meta_soft") return std::make_unique<MetaSoftMatte>(ctx);
  std::string known;
  for (const auto& n : all_method_names()) known += " " + n;
  known += " cvf_local";
  throw std::invalid_argument("unknown occlusion method '" + name + "' (known:" + known + ")");
}

}  // namespace probeless::eval
