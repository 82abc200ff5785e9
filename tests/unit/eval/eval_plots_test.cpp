#include "lab/eval/eval_plots.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>

#include "lab/eval/bar_chart.hpp"
#include "lab/eval/occlusion_eval.hpp"
#include "support/test_data.hpp"
#include "unit/eval/xml_tree.hpp"

namespace probeless::eval {
namespace {

namespace fs = std::filesystem;
using testing::XmlElement;
using testing::XmlReader;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Two scenes of a protocol without temporal noise (one frame) or SAD (no matting case);
// the boundary MSE is missing where a scene has no silhouette.
EvalReport two_scene_report() {
  EvalReport r;
  r.protocol = "middlebury";
  r.methods = {"cvf", "direct1"};
  const auto score = [](double mse, std::optional<double> boundary_mse) {
    MethodScore s;
    s.mse = mse;
    s.boundary_mse = boundary_mse;
    return s;
  };
  SceneScores a{"v2/venus", {}}, b{"v2/cones", {}};
  a.methods["cvf"] = score(0.002, 0.01);
  a.methods["direct1"] = score(0.004, 0.02);
  b.methods["cvf"] = score(0.001, std::nullopt);
  b.methods["direct1"] = score(0.003, std::nullopt);
  r.scenes = {a, b};
  r.mean["cvf"] = score(0.0015, 0.01);
  r.mean["direct1"] = score(0.0035, 0.02);
  return r;
}

TEST(EvalPlots, WritesOneSvgPerMeasuredMetric) {
  const auto dir = probeless::testing::scratch_dir() / "plots";
  write_bar_plots(dir, two_scene_report());
  EXPECT_TRUE(fs::exists(dir / "mse.svg"));
  EXPECT_TRUE(fs::exists(dir / "boundary_mse.svg"));
  EXPECT_FALSE(fs::exists(dir / "temporal_noise.svg"));  // not measured: no empty plot
  EXPECT_FALSE(fs::exists(dir / "sad.svg"));
  for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().extension(), ".svg");

  const XmlElement mse = XmlReader::parse(slurp(dir / "mse.svg"));
  EXPECT_EQ(mse.children.at(0).text, "MSE per scene and method");
  std::vector<std::string> texts;
  for (const auto* t : mse.find_all("text")) texts.push_back(t->text);
  for (const char* t : {"v2/venus", "v2/cones", "mean", "cvf", "direct1", "MSE", "0.005"})
    EXPECT_NE(std::find(texts.begin(), texts.end(), t), texts.end()) << t;
  // Every method has a bar per scene and one for the mean, its value in the tooltip.
  for (const auto* g : mse.find_all("g")) {
    const auto bars = g->find_all("rect");
    ASSERT_EQ(bars.size(), 3U) << g->attr("data-name");
    EXPECT_EQ(
        bars[2]->children.at(0).text,
        g->attr("data-name") + ", mean: " + (g->attr("data-name") == "cvf" ? "0.0015" : "0.0035"));
  }
  EXPECT_EQ(mse.find_all("g").size(), 2U);

  // Scores only where there is a silhouette: venus and the mean.
  const XmlElement boundary = XmlReader::parse(slurp(dir / "boundary_mse.svg"));
  for (const auto* g : boundary.find_all("g")) EXPECT_EQ(g->find_all("rect").size(), 2U);
}

// A stabilised variant is drawn in its method's colour, paler; the next method takes the
// next colour, so that colours follow methods whether or not --stabilised was given.
TEST(EvalPlots, StabilisedVariantsShareTheirMethodsColour) {
  EvalReport r = two_scene_report();
  r.methods = {"cvf", stabilised_name("cvf"), "direct1"};
  for (auto* scores : {&r.scenes[0].methods, &r.scenes[1].methods, &r.mean})
    (*scores)[stabilised_name("cvf")] = (*scores)["cvf"];
  const auto dir = probeless::testing::scratch_dir() / "plots";
  write_bar_plots(dir, r);
  const XmlElement mse = XmlReader::parse(slurp(dir / "mse.svg"));
  std::map<std::string, std::string> fill;
  for (const auto* g : mse.find_all("g"))
    fill[g->attr("data-name")] = g->find_all("rect").at(0)->attr("fill");
  EXPECT_EQ(fill.at("cvf"), series_colour(0));
  EXPECT_EQ(fill.at("cvf+stab"), series_colour(0, true));
  EXPECT_EQ(fill.at("direct1"), series_colour(1));
  EXPECT_NE(fill.at("cvf"), fill.at("cvf+stab"));
}

}  // namespace
}  // namespace probeless::eval
