#include "lab/eval/method_set.hpp"

#include <algorithm>
#include <stdexcept>

#include "kernels/occlusion/method_registry.hpp"

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
    const auto trace = cvf_local_reference(in.colour->download(q), in.real_depth_mm->download(q),
                                           in.virtual_depth_mm->download(q), params_);
    alpha.upload(q, trace.alpha);
  }

 private:
  ComputeContext& ctx_;
  CvfLocalParams params_;
};

}  // namespace

const std::vector<std::string>& all_method_names() {
  return occlusion::method_names();
}

std::unique_ptr<OcclusionMethod> make_method(ComputeContext& ctx, const std::string& name,
                                             const MethodSettings& settings) {
  if (name == "cvf_local") {
    CvfLocalParams p = settings.cvf_local;
    p.cvf.categorise = settings.cvf.categorise;
    return std::make_unique<CvfLocalHostMethod>(ctx, p);
  }
  const auto& names = all_method_names();
  if (std::find(names.begin(), names.end(), name) != names.end())
    return occlusion::make_method(ctx, name, settings.cvf);
  std::string known;
  for (const auto& n : names) known += " " + n;
  known += " cvf_local";
  throw std::invalid_argument("unknown occlusion method '" + name + "' (known:" + known + ")");
}

}  // namespace probeless::eval
