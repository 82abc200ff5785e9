#include "lab/eval/occlusion_eval.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <stdexcept>

#include "kernels/occlusion/temporal/matte_stabiliser.hpp"
#include "lab/eval/alphamatting_dataset.hpp"
#include "lab/eval/eval_plots.hpp"
#include "lab/eval/frames_dataset.hpp"
#include "lab/eval/matte_metrics.hpp"
#include "lab/eval/middlebury_dataset.hpp"
#include "lab/eval/sim_dataset.hpp"
#include "lab/eval/sim_metrics.hpp"

namespace probeless::eval {
namespace fs = std::filesystem;

std::vector<EvalCase> load_cases(const std::string& spec, const EvalOptions& options,
                                 std::string* protocol) {
  if (spec == "sim" || spec.rfind("sim:", 0) == 0) {
    if (options.crop_width > 0 || options.crop_height > 0)
      throw std::invalid_argument(
          "dataset 'sim': --crop is not supported (the poses and "
          "intrinsics are the full frame's)");
    if (protocol) *protocol = "sim";
    return sim_cases(parse_sim_protocol(spec.size() > 4 ? spec.substr(4) : std::string()));
  }
  const auto colon = spec.find(':');
  if (colon == std::string::npos || colon + 1 == spec.size())
    throw std::invalid_argument(
        "dataset '" + spec +
        "': expected middlebury:DIR, alphamatting:DIR, frames:DIR or sim[:OPTIONS]");
  const std::string kind = spec.substr(0, colon);
  const fs::path dir = spec.substr(colon + 1);
  std::vector<EvalCase> cases;
  if (kind == "middlebury") {
    auto scenes = find_middlebury_scenes(dir);
    if (options.max_scenes > 0 && scenes.size() > static_cast<std::size_t>(options.max_scenes))
      scenes.resize(options.max_scenes);
    for (const auto& s : scenes) {
      spdlog::info("eval: loading {}", s.string());
      auto scene = load_middlebury_scene(s);
      // Scenes of the same name in both layouts stay apart.
      if (s.parent_path().filename() == "v2" || s.parent_path().filename() == "2014q")
        scene.name = s.parent_path().filename().string() + "/" + scene.name;
      for (auto& c : middlebury_cases(scene, {options.frames, options.seed}))
        cases.push_back(std::move(c));
    }
  } else if (kind == "alphamatting") {
    cases = alphamatting_cases(dir);
    if (options.max_scenes > 0 && cases.size() > static_cast<std::size_t>(options.max_scenes))
      cases.resize(options.max_scenes);
  } else if (kind == "frames") {
    cases = recorded_cases(dir);
  } else {
    throw std::invalid_argument("dataset kind '" + kind +
                                "' unknown: expected middlebury, alphamatting, frames or sim");
  }
  for (auto& c : cases)
    for (auto& f : c.frames) crop_center(f, options.crop_width, options.crop_height);
  if (protocol) *protocol = kind;
  return cases;
}

namespace {

// Mean over the frames that have pixels in `regions` of the frame's MSE there.
std::optional<double> mean_region_mse(const std::vector<ImageF>& alphas, const EvalCase& c,
                                      ImageGray8 EvalFrame::*region) {
  double sum = 0;
  int n = 0;
  for (std::size_t k = 0; k < c.frames.size(); ++k) {
    const ImageGray8& m = c.frames[k].*region;
    if (m.empty()) continue;
    if (auto v = matte_mse(alphas[k], c.frames[k].truth, m)) sum += *v, ++n;
  }
  if (!n) return std::nullopt;
  return sum / n;
}

// The mean over the frames that have one (SimComposite::error's -1: none).
std::optional<double> mean_composite_error(const std::vector<CompositeErrors>& errors,
                                           bool estimated) {
  double sum = 0;
  int n = 0;
  for (const CompositeErrors& e : errors)
    if (const double v = estimated ? e.estimated : e.observed; v >= 0) sum += v, ++n;
  return n ? std::optional(sum / n) : std::nullopt;
}

MethodScore score(const EvalCase& c, const std::vector<ImageF>& alphas,
                  const std::vector<ImageF>& truths, const std::vector<ImageGray8>& masks,
                  const std::vector<ImageGray8>& bands,
                  const std::vector<CompositeErrors>& composite_errors) {
  MethodScore s;
  double mse_sum = 0, band_sum = 0, sad_sum = 0;
  int mse_n = 0, band_n = 0;
  for (std::size_t k = 0; k < c.frames.size(); ++k) {
    if (auto v = matte_mse(alphas[k], truths[k], masks[k])) {
      mse_sum += *v;
      ++mse_n;
    }
    if (auto v = matte_mse(alphas[k], truths[k], bands[k])) {
      band_sum += *v;
      ++band_n;
    }
    sad_sum += matte_sad(alphas[k], truths[k], masks[k]);
  }
  s.mse = mse_n ? mse_sum / mse_n : 0.0;
  if (band_n) s.boundary_mse = band_sum / band_n;
  s.temporal_noise = windowed_temporal_noise(alphas, truths, masks, c.temporal_window);
  if (c.report_sad) s.sad = sad_sum / static_cast<double>(c.frames.size());
  s.contact_mse = mean_region_mse(alphas, c, &EvalFrame::contact_band);
  s.near_occluder_mse = mean_region_mse(alphas, c, &EvalFrame::near_band);
  s.fg_composite_error = mean_composite_error(composite_errors, true);
  s.observed_composite_error = mean_composite_error(composite_errors, false);
  return s;
}

}  // namespace

EvalReport evaluate(ComputeContext& ctx, const std::vector<EvalCase>& cases,
                    const EvalOptions& options) {
  EvalReport report;
  // The report's columns: every method, and with options.stabilised its stabilised variant.
  for (const auto& name : options.methods) {
    report.methods.push_back(name);
    if (options.stabilised) report.methods.push_back(stabilised_name(name));
  }
  std::vector<std::unique_ptr<occlusion::OcclusionMethod>> methods;
  for (const auto& name : options.methods)
    methods.push_back(make_method(ctx, name, options.settings));
  auto& queue = ctx.queue();
  SimComposite composite(ctx);
  std::vector<CompositeErrors> true_matte_errors;

  for (const auto& c : cases) {
    spdlog::info("eval: {} ({} frame{})", c.name, c.frames.size(), c.frames.size() == 1 ? "" : "s");
    const std::size_t columns = report.methods.size();
    std::vector<std::vector<ImageF>> alphas(columns);
    std::vector<std::vector<CompositeErrors>> composite_errors(columns);
    // One stabiliser per method and case: its history is that method's previous matte.
    std::vector<std::unique_ptr<occlusion::MatteStabiliser>> stabilisers;
    if (options.stabilised)
      for (std::size_t m = 0; m < methods.size(); ++m)
        stabilisers.push_back(
            std::make_unique<occlusion::MatteStabiliser>(ctx, options.stabiliser));
    const PinholeIntrinsics k = c.intrinsics.value_or(PinholeIntrinsics{});
    DeviceImageRGB8 colour;
    DeviceDepthImage depth;
    DeviceImageF virt, alpha;
    DepthImage judged_depth;
    BeyondRangeScratch scratch;
    for (const auto& f : c.frames) {
      colour.upload(queue, f.colour);
      judged_depth = f.real_depth_mm;
      fill_beyond_range_holes(judged_depth, options.beyond_range, scratch);
      depth.upload(queue, judged_depth);
      virt.upload(queue, f.virtual_depth_mm);
      if (!f.virtual_colour.empty()) {
        alpha.upload(queue, f.truth);
        true_matte_errors.push_back(composite.error(f, colour, virt, alpha, f.truth));
      }
      const occlusion::OcclusionInputs in{&colour, &depth, &virt};
      std::size_t column = 0;
      for (std::size_t m = 0; m < methods.size(); ++m) {
        methods[m]->process(in, alpha);
        alphas[column].push_back(alpha.download(queue));
        composite_errors[column].push_back(
            composite.error(f, colour, virt, alpha, alphas[column].back()));
        ++column;
        if (options.stabilised) {
          stabilisers[m]->process(methods[m]->as_judged(in), c.intrinsics ? k : PinholeIntrinsics{},
                                  f.T_world_camera, alpha);
          alphas[column].push_back(alpha.download(queue));
          composite_errors[column].push_back(
              composite.error(f, colour, virt, alpha, alphas[column].back()));
          ++column;
        }
      }
    }
    SceneScores scene{c.name, {}};
    std::vector<ImageF> truths;
    std::vector<ImageGray8> masks, bands;
    for (const auto& f : c.frames) {
      truths.push_back(f.truth);
      masks.push_back(f.mask);
      bands.push_back(silhouette_band(f.truth, f.mask, options.boundary_px));
    }
    for (std::size_t m = 0; m < columns; ++m)
      scene.methods[report.methods[m]] =
          score(c, alphas[m], truths, masks, bands, composite_errors[m]);
    if (!options.plots_dir.empty())
      write_example_mattes(options.plots_dir, c, report.methods, alphas);
    report.scenes.push_back(std::move(scene));
  }

  for (const auto& name : report.methods) {
    MethodScore mean;
    struct Acc {
      double sum = 0;
      int n = 0;
      void add(const std::optional<double>& v) {
        if (v) sum += *v, ++n;
      }
      std::optional<double> get() const { return n ? std::optional(sum / n) : std::nullopt; }
    } b, t, sd, ct, nr, fg, ob;
    for (const auto& sc : report.scenes) {
      const auto& s = sc.methods.at(name);
      mean.mse += s.mse / static_cast<double>(report.scenes.size());
      b.add(s.boundary_mse);
      t.add(s.temporal_noise);
      sd.add(s.sad);
      ct.add(s.contact_mse);
      nr.add(s.near_occluder_mse);
      fg.add(s.fg_composite_error);
      ob.add(s.observed_composite_error);
    }
    mean.boundary_mse = b.get();
    mean.temporal_noise = t.get();
    mean.sad = sd.get();
    mean.contact_mse = ct.get();
    mean.near_occluder_mse = nr.get();
    mean.fg_composite_error = fg.get();
    mean.observed_composite_error = ob.get();
    report.mean[name] = mean;
  }
  const auto true_estimated = mean_composite_error(true_matte_errors, true),
             true_observed = mean_composite_error(true_matte_errors, false);
  if (true_estimated && true_observed)
    report.true_matte_composite = CompositeErrors{*true_estimated, *true_observed};
  if (!options.plots_dir.empty()) write_bar_plots(options.plots_dir, report);
  return report;
}

namespace {

std::string table(const EvalReport& r, const char* title, double scale,
                  std::optional<double> (*get)(const MethodScore&)) {
  bool any = false;
  for (const auto& [n, s] : r.mean) any = any || get(s).has_value();
  if (!any) return {};
  std::size_t name_w = 8;
  for (const auto& sc : r.scenes) name_w = std::max(name_w, sc.name.size());
  std::string out = fmt::format("{:<{}}", title, name_w);
  for (const auto& m : r.methods) out += fmt::format(" {:>11}", m);
  out += "\n";
  auto row = [&](const std::string& name, const std::map<std::string, MethodScore>& scores) {
    out += fmt::format("{:<{}}", name, name_w);
    for (const auto& m : r.methods) {
      const auto v = get(scores.at(m));
      out += v ? fmt::format(" {:>11.3f}", *v * scale) : fmt::format(" {:>11}", "-");
    }
    out += "\n";
  };
  for (const auto& sc : r.scenes) row(sc.name, sc.methods);
  row("mean", r.mean);
  return out + "\n";
}

}  // namespace

std::string format_report(const EvalReport& r) {
  std::string out;
  out += table(r, "MSE x1e3", 1e3, [](const MethodScore& s) { return std::optional(s.mse); });
  out += table(r, "boundary MSE x1e3", 1e3, [](const MethodScore& s) { return s.boundary_mse; });
  out +=
      table(r, "temporal noise x1e3", 1e3, [](const MethodScore& s) { return s.temporal_noise; });
  out += table(r, "SAD /1000", 1.0, [](const MethodScore& s) { return s.sad; });
  out += table(r, "contact MSE x1e3", 1e3, [](const MethodScore& s) { return s.contact_mse; });
  out += table(r, "near-occluder MSE x1e3", 1e3,
               [](const MethodScore& s) { return s.near_occluder_mse; });
  out += table(r, "fg composite error x1e3", 1e3,
               [](const MethodScore& s) { return s.fg_composite_error; });
  out += table(r, "composite error, observed colour x1e3", 1e3,
               [](const MethodScore& s) { return s.observed_composite_error; });
  if (const auto& t = r.true_matte_composite)
    out += fmt::format(
        "composite error with the true matte x1e3: {:.3f} with the foreground estimate, {:.3f} "
        "with the observed colour\n\n",
        1e3 * t->estimated, 1e3 * t->observed);
  return out;
}

nlohmann::json report_json(const EvalReport& r) {
  auto score = [](const MethodScore& s) {
    nlohmann::json j;
    j["mse"] = s.mse;
    if (s.boundary_mse) j["boundary_mse"] = *s.boundary_mse;
    if (s.temporal_noise) j["temporal_noise"] = *s.temporal_noise;
    if (s.sad) j["sad"] = *s.sad;
    if (s.contact_mse) j["contact_mse"] = *s.contact_mse;
    if (s.near_occluder_mse) j["near_occluder_mse"] = *s.near_occluder_mse;
    if (s.fg_composite_error) j["fg_composite_error"] = *s.fg_composite_error;
    if (s.observed_composite_error) j["observed_composite_error"] = *s.observed_composite_error;
    return j;
  };
  nlohmann::json j;
  j["protocol"] = r.protocol;
  j["scenes"] = nlohmann::json::array();
  for (const auto& sc : r.scenes) {
    nlohmann::json methods = nlohmann::json::object();
    for (const auto& m : r.methods) methods[m] = score(sc.methods.at(m));
    j["scenes"].push_back({{"name", sc.name}, {"methods", methods}});
  }
  nlohmann::json mean = nlohmann::json::object();
  for (const auto& m : r.methods) mean[m] = score(r.mean.at(m));
  j["mean"] = mean;
  if (const auto& t = r.true_matte_composite)
    j["true_matte"] = {{"fg_composite_error", t->estimated},
                       {"observed_composite_error", t->observed}};
  return j;
}

}  // namespace probeless::eval
