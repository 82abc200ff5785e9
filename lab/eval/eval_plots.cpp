#include "lab/eval/eval_plots.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <stdexcept>

#include "drivers/io/png.hpp"
#include "lab/eval/bar_chart.hpp"
#include "lab/eval/occlusion_eval.hpp"

namespace probeless::eval {
namespace fs = std::filesystem;
namespace {

using Metric = std::optional<double> (*)(const MethodScore&);

std::optional<double> score_of(const std::map<std::string, MethodScore>& scores,
                               const std::string& method, Metric metric) {
  const auto it = scores.find(method);
  return it == scores.end() ? std::nullopt : metric(it->second);
}

// Scenes left to right, then their mean after a rule; one series per method, report order.
BarChart metric_chart(const EvalReport& r, std::string title, std::string value_label,
                      Metric metric) {
  BarChart chart;
  chart.title = std::move(title);
  chart.value_label = std::move(value_label);
  for (const auto& scene : r.scenes) chart.groups.push_back(scene.name);
  chart.groups.emplace_back("mean");
  chart.separator_before = r.scenes.size();
  std::size_t colours = 0;
  for (const auto& method : r.methods) {
    BarSeries s;
    s.name = method;
    // A stabilised variant in its method's colour, paler (report order puts it right after).
    const bool variant = colours > 0 && method == stabilised_name(chart.series.back().name);
    s.colour = variant ? series_colour(colours - 1, true) : series_colour(colours++);
    for (const auto& scene : r.scenes) s.values.push_back(score_of(scene.methods, method, metric));
    s.values.push_back(score_of(r.mean, method, metric));
    chart.series.push_back(std::move(s));
  }
  return chart;
}

// Nothing is written for a metric the protocol does not measure (no bars at all).
void write_chart(const fs::path& path, const BarChart& chart) {
  if (!has_bars(chart)) return;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bar_chart_svg(chart);
  out.close();
  if (!out) throw std::runtime_error(path.string() + ": cannot write the plot");
}

std::string file_stem(const std::string& case_name) {
  std::string s = case_name;
  std::replace(s.begin(), s.end(), '/', '_');
  return s;
}

ImageGray8 to_gray(const ImageF& a) {
  ImageGray8 g(a.width(), a.height());
  for (std::size_t i = 0; i < a.pixel_count(); ++i)
    g.data()[i] = static_cast<std::uint8_t>(std::lround(std::clamp(a.data()[i], 0.0F, 1.0F) * 255));
  return g;
}

}  // namespace

void write_example_mattes(const fs::path& dir, const EvalCase& c,
                          const std::vector<std::string>& methods,
                          const std::vector<std::vector<ImageF>>& alphas) {
  if (c.frames.empty()) return;
  fs::create_directories(dir);
  const auto stem = file_stem(c.name);
  write_png(dir / (stem + "_color.png"), c.frames[0].colour);
  write_png(dir / (stem + "_truth.png"), to_gray(c.frames[0].truth));
  for (std::size_t m = 0; m < methods.size(); ++m)
    if (!alphas[m].empty())
      write_png(dir / (stem + "_" + methods[m] + ".png"), to_gray(alphas[m][0]));
}

void write_bar_plots(const fs::path& dir, const EvalReport& r) {
  fs::create_directories(dir);
  write_chart(dir / "mse.svg",
              metric_chart(r, "MSE per scene and method", "MSE",
                           [](const MethodScore& s) { return std::optional(s.mse); }));
  write_chart(dir / "boundary_mse.svg",
              metric_chart(r, "MSE within 10 px of true silhouettes", "boundary MSE",
                           [](const MethodScore& s) { return s.boundary_mse; }));
  write_chart(dir / "temporal_noise.svg",
              metric_chart(r, "Temporal noise (per-pixel variance across frames)", "variance",
                           [](const MethodScore& s) { return s.temporal_noise; }));
  write_chart(dir / "sad.svg", metric_chart(r, "SAD per scene and method", "SAD / 1000",
                                            [](const MethodScore& s) { return s.sad; }));
}

}  // namespace probeless::eval
