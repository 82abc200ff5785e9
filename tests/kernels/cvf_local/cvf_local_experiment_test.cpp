// The measurement behind docs/occlusion.md "Local colour models (proposed CVF change)": the CPU
// references of CVF, of the local-colour-model variants and of the Bilateral and Guided
// baselines on the evaluator's own cases, per-scene MSE and temporal noise to stdout.
// An experiment, not a test (it cannot fail), hence DISABLED_; run it with
//   PROBELESS_DATA=../shared/data build/release/tests/test_kernels_cvf_local
//     --gtest_also_run_disabled_tests --gtest_filter='*Experiment*'   (one line)
// CVF_LOCAL_DATASET=alphamatting switches protocol, CVF_LOCAL_FRAMES sets K (default 8).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <map>
#include <string>

#include "drivers/io/png.hpp"
#include "kernels/occlusion/baselines/bilateral_matte_reference.hpp"
#include "kernels/occlusion/baselines/guided_matte_reference.hpp"
#include "kernels/occlusion/common/categorise_reference.hpp"
#include "kernels/occlusion/cvf/cvf_local_reference.hpp"
#include "kernels/occlusion/cvf/cvf_reference.hpp"
#include "lab/eval/matte_metrics.hpp"
#include "lab/eval/occlusion_eval.hpp"
#include "support/test_data.hpp"

namespace probeless::occlusion {
namespace {

using Method = std::function<ImageF(const eval::EvalFrame&, const CvfParams&)>;

std::vector<std::pair<std::string, Method>> methods() {
  std::vector<std::pair<std::string, Method>> m;
  m.emplace_back("cvf", [](const eval::EvalFrame& f, const CvfParams& p) {
    return cvf_reference(f.colour, f.real_depth_mm, f.virtual_depth_mm, p).alpha;
  });
  m.emplace_back("bilateral", [](const eval::EvalFrame& f, const CvfParams& p) {
    BilateralMatteParams b;
    b.categorise = p.categorise;
    return bilateral_matte_reference(f.colour, f.real_depth_mm, f.virtual_depth_mm, b);
  });
  m.emplace_back("guided", [](const eval::EvalFrame& f, const CvfParams& p) {
    GuidedMatteParams g;
    g.categorise = p.categorise;
    g.filter = {p.wide.radius, p.wide.eps, 1};
    return guided_matte_reference(f.colour, f.real_depth_mm, f.virtual_depth_mm, g);
  });
  auto local = [&m](const std::string& name, std::function<void(CvfLocalParams&)> set) {
    m.emplace_back(name, [set](const eval::EvalFrame& f, const CvfParams& p) {
      CvfLocalParams lp;
      lp.cvf.categorise = p.categorise;  // the protocol's (erosion 0 for matting)
      set(lp);
      return cvf_local_reference(f.colour, f.real_depth_mm, f.virtual_depth_mm, lp).alpha;
    });
  };
  // The proposed default, then one change at a time (docs/occlusion.md, the ablation table).
  local("cvf_local", [](CvfLocalParams&) {});
  local("global", [](CvfLocalParams& lp) { lp.tile_px = 0; });
  local("tile64", [](CvfLocalParams& lp) { lp.tile_px = 64; });
  local("no_prior", [](CvfLocalParams& lp) { lp.prior_radius = 0; });
  local("hard", [](CvfLocalParams& lp) { lp.soft_where_ambiguous = false; });
  local("cvf_filt", [](CvfLocalParams& lp) {
    const CvfParams cvf;  // CVF's own wide (r 6, half resolution) and feather (eps 0.3)
    lp.cvf.wide = cvf.wide;
    lp.cvf.feather = cvf.feather;
  });
  return m;
}

// Colour on the left, categories on the right (infront red, behind blue, process green,
// truth's silhouettes white).
ImageRGB8 category_panel(const eval::EvalFrame& f, const CvfParams& p) {
  const auto cats = categorise_reference(f.real_depth_mm, f.virtual_depth_mm, p.categorise);
  const int w = f.colour.width(), h = f.colour.height();
  ImageRGB8 out(2 * w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = f.colour.at(x, y, k);
      const auto c = static_cast<Category>(cats.at(x, y));
      const std::uint8_t v = f.truth.at(x, y) > 0.5F ? 255 : 90;
      out.at(w + x, y, 0) = c == Category::Infront ? v : 0;
      out.at(w + x, y, 1) = c == Category::Process ? v : 0;
      out.at(w + x, y, 2) = c == Category::Behind ? v : 0;
    }
  return out;
}
// Signed error of a matte, on grey: red = shown where hidden, blue = hidden where shown.
ImageRGB8 error_panel(const eval::EvalFrame& f, const ImageF& alpha) {
  const int w = f.colour.width(), h = f.colour.height();
  ImageRGB8 out(2 * w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float e = f.mask.at(x, y) ? alpha.at(x, y) - f.truth.at(x, y) : 0.0F;
      const auto a = static_cast<std::uint8_t>(255 * std::clamp(alpha.at(x, y), 0.0F, 1.0F));
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = a;
      out.at(w + x, y, 0) = static_cast<std::uint8_t>(60 + 195 * std::max(0.0F, e));
      out.at(w + x, y, 1) = 60;
      out.at(w + x, y, 2) = static_cast<std::uint8_t>(60 + 195 * std::max(0.0F, -e));
    }
  return out;
}
// Left: categories again; right: where `alpha` has a larger squared error than `other` (red)
// or a smaller one (green).
ImageRGB8 diff_panel(const eval::EvalFrame& f, const ImageF& alpha, const ImageF& other) {
  const int w = f.colour.width(), h = f.colour.height();
  ImageRGB8 out(2 * w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = f.colour.at(x, y, k) / 2;
      if (!f.mask.at(x, y)) continue;
      const float ea = alpha.at(x, y) - f.truth.at(x, y), eo = other.at(x, y) - f.truth.at(x, y);
      const float d = ea * ea - eo * eo;
      out.at(w + x, y, 0) = static_cast<std::uint8_t>(40 + 215 * std::clamp(d, 0.0F, 1.0F));
      out.at(w + x, y, 1) = static_cast<std::uint8_t>(40 + 215 * std::clamp(-d, 0.0F, 1.0F));
      out.at(w + x, y, 2) = 40;
    }
  return out;
}
ImageRGB8 stack(const std::vector<ImageRGB8>& panels) {
  ImageRGB8 out(panels[0].width(), panels[0].height() * int(panels.size()));
  for (std::size_t i = 0; i < panels.size(); ++i)
    for (int y = 0; y < panels[i].height(); ++y)
      std::copy(panels[i].row(y), panels[i].row(y) + panels[i].row_elements(),
                out.row(int(i) * panels[0].height() + y));
  return out;
}

TEST(CvfLocalExperiment, DISABLED_PerSceneMse) {
  PROBELESS_REQUIRE_DATA("middlebury");
  const char* ds = std::getenv("CVF_LOCAL_DATASET");
  const std::string kind = ds ? ds : "middlebury";
  eval::EvalOptions opts;
  if (const char* k = std::getenv("CVF_LOCAL_FRAMES")) opts.frames = std::atoi(k);
  if (const char* sd = std::getenv("CVF_LOCAL_SEED")) opts.seed = std::strtoull(sd, nullptr, 10);
  const auto cases =
      eval::load_cases(kind + ":" + (testing::shared_data_dir() / kind).string(), opts, nullptr);
  CvfParams params;
  if (kind == "alphamatting") params.categorise.erosion_px = 0;  // as the eval command
  const auto ms = methods();
  std::string head = fmt::format("{:<26}", "MSE x1e3");
  for (const auto& [n, f] : ms) head += fmt::format(" {:>9}", n);
  std::printf("%s\n", head.c_str());
  std::map<std::string, double> mean_mse, mean_tn;
  std::map<std::string, int> wins;
  for (const auto& c : cases) {
    std::string row = fmt::format("{:<26}", c.name);
    std::vector<ImageF> truths;
    std::vector<ImageGray8> masks;
    for (const auto& f : c.frames) {
      truths.push_back(f.truth);
      masks.push_back(f.mask);
    }
    const char* dump = std::getenv("CVF_LOCAL_DUMP");
    std::vector<ImageRGB8> panels;
    ImageF bil0;
    const std::string dump_method =
        std::getenv("CVF_LOCAL_DUMP_METHOD") ? std::getenv("CVF_LOCAL_DUMP_METHOD") : "cvf";
    if (dump) panels.push_back(category_panel(c.frames[0], params));
    double best = 1e9;
    std::string best_name;
    for (const auto& [n, fn] : ms) {
      std::vector<ImageF> alphas;
      double sum = 0;
      int cnt = 0;
      for (const auto& f : c.frames) {
        alphas.push_back(fn(f, params));
        if (auto v = eval::matte_mse(alphas.back(), f.truth, f.mask)) sum += *v, ++cnt;
      }
      const double mse = cnt ? sum / cnt : 0.0;
      if (std::getenv("CVF_LOCAL_SPLIT")) {
        // Contribution to frame 0's MSE by category: ignore, behind, infront, process.
        const auto& f0 = c.frames[0];
        const auto cats =
            categorise_reference(f0.real_depth_mm, f0.virtual_depth_mm, params.categorise);
        double e[4] = {0, 0, 0, 0};
        int n_eval = 0;
        for (int y = 0; y < f0.truth.height(); ++y)
          for (int x = 0; x < f0.truth.width(); ++x) {
            if (!f0.mask.at(x, y)) continue;
            ++n_eval;
            const double d = alphas[0].at(x, y) - f0.truth.at(x, y);
            e[cats.at(x, y)] += d * d;
          }
        std::printf("  %-10s ign %.2f beh %.2f inf %.2f proc %.2f\n", n.c_str(),
                    1e3 * e[0] / n_eval, 1e3 * e[1] / n_eval, 1e3 * e[2] / n_eval,
                    1e3 * e[3] / n_eval);
      }
      mean_mse[n] += mse / double(cases.size());
      if (auto tn = eval::temporal_noise(alphas, truths, masks))
        mean_tn[n] += *tn / double(cases.size());
      const bool baseline = n == "bilateral" || n == "guided";
      if (baseline && mse < best) best = mse, best_name = n;
      row += fmt::format(" {:>9.3f}", mse * 1e3);
      if (!baseline && n != "cvf" && mse <= best) wins[n]++;
      if (dump && (n == "bilateral" || n == dump_method))
        panels.push_back(error_panel(c.frames[0], alphas[0]));
      if (dump && n == "bilateral") bil0 = alphas[0];
      if (dump && n == dump_method) panels.push_back(diff_panel(c.frames[0], alphas[0], bil0));
    }
    std::printf("%s\n", row.c_str());
    std::fflush(stdout);
    if (dump) {
      std::string file = c.name;
      for (auto& ch : file) ch = ch == '/' ? '_' : ch;
      write_png(std::filesystem::path(dump) / (file + ".png"), stack(panels));
    }
  }
  std::string mrow = fmt::format("{:<26}", "mean"), trow = fmt::format("{:<26}", "temporal x1e3"),
              wrow = fmt::format("{:<26}", "beats cvf-free baselines");
  for (const auto& [n, f] : ms) {
    mrow += fmt::format(" {:>9.3f}", mean_mse[n] * 1e3);
    trow += fmt::format(" {:>9.3f}", mean_tn[n] * 1e3);
    wrow += fmt::format(" {:>9}", wins[n]);
  }
  std::printf("%s\n%s\n%s\n", mrow.c_str(), trow.c_str(), wrow.c_str());
}

}  // namespace
}  // namespace probeless::occlusion
