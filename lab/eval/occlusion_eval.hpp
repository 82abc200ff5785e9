#pragma once
// `probeless eval occlusion`: runs every occlusion method over the cases of a protocol and
// scores the mattes (lab/eval/matte_metrics.hpp). docs/occlusion.md "Evaluation".
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/beyond_range.hpp"
#include "kernels/occlusion/temporal/matte_stabiliser_params.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "lab/eval/eval_case.hpp"
#include "lab/eval/method_set.hpp"
#include "lab/eval/sim_metrics.hpp"

namespace probeless::eval {

struct MethodScore {
  double mse = 0;
  std::optional<double> boundary_mse;    // absent when the case has no silhouette
  std::optional<double> temporal_noise;  // absent with one frame
  std::optional<double> sad;             // matting cases
  // The sim protocol's (absent elsewhere): MSE in the band around the virtual objects'
  // contact lines, in the band around an occluder without depth, and the composite's mean
  // squared error (RGB / 255) where the matte is fractional against the composite with the
  // true matte and the true foreground colour: fg_composite_error with the service's
  // foreground colour estimate, observed_composite_error with the observed colour.
  std::optional<double> contact_mse;
  std::optional<double> near_occluder_mse;
  std::optional<double> fg_composite_error;
  std::optional<double> observed_composite_error;
};

struct SceneScores {
  std::string name;
  std::map<std::string, MethodScore> methods;
};

struct EvalReport {
  std::string protocol;
  std::vector<std::string> methods;  // report order
  std::vector<SceneScores> scenes;
  std::map<std::string, MethodScore> mean;  // arithmetic mean over scenes
  // The sim protocol's composite error with the true matte (mean over its frames): what the
  // foreground estimate alone does where the matte is right. Absent elsewhere.
  std::optional<CompositeErrors> true_matte_composite;
};

struct EvalOptions {
  std::vector<std::string> methods = all_method_names();
  MethodSettings settings;
  int frames = 8;  // K (Middlebury)
  std::uint64_t seed = 1;
  int crop_width = 0, crop_height = 0;  // centre crop; 0 = whole frames
  int boundary_px = 10;
  int max_scenes = 0;               // 0 = all
  std::filesystem::path plots_dir;  // empty = no plots
  // Also score every method with temporal stabilisation ("<method>+stab"), the frames' poses
  // giving the camera's motion (identity without them).
  bool stabilised = false;
  occlusion::StabiliserParams stabiliser;
  // The service's pass over the sensor's depth before any method (app/pipeline UploadStage):
  // beyond-range holes filled far. far_mm 0 gives every method the depth as recorded.
  BeyondRangeRule beyond_range;
};

// The name of a method's stabilised variant in the report.
inline std::string stabilised_name(const std::string& method) {
  return method + "+stab";
}

// "middlebury:DIR", "alphamatting:DIR", "frames:DIR" or "sim[:OPTIONS]" (sim_dataset.hpp). Throws
// std::invalid_argument for a bad spec, ImageFileError for a malformed dataset.
std::vector<EvalCase> load_cases(const std::string& dataset_spec, const EvalOptions& options,
                                 std::string* protocol = nullptr);

// Runs and scores; writes example mattes into options.plots_dir when set.
EvalReport evaluate(ComputeContext& ctx, const std::vector<EvalCase>& cases,
                    const EvalOptions& options);

// One table per metric: scenes down, methods across, then the mean.
std::string format_report(const EvalReport& report);
nlohmann::json report_json(const EvalReport& report);

}  // namespace probeless::eval
