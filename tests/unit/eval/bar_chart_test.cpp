#include "lab/eval/bar_chart.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <locale>
#include <numbers>
#include <set>
#include <string>

#include "lab/eval/svg_document.hpp"
#include "unit/eval/xml_tree.hpp"

namespace probeless::eval {
namespace {

using testing::XmlElement;
using testing::XmlReader;

struct Box {
  double x, y, w, h;
};

Box box_of(const XmlElement& rect) {
  return {std::stod(rect.attr("x")), std::stod(rect.attr("y")), std::stod(rect.attr("width")),
          std::stod(rect.attr("height"))};
}

const XmlElement& only(const XmlElement& root, std::string_view name, const std::string& key,
                       const std::string& value) {
  const XmlElement* found = nullptr;
  for (const auto* e : root.find_all(name)) {
    const auto it = e->attributes.find(key);
    if (it == e->attributes.end() || it->second != value) continue;
    EXPECT_EQ(found, nullptr) << "two <" << name << " " << key << "=" << value << ">";
    found = e;
  }
  if (found == nullptr) throw std::runtime_error("no <" + std::string(name) + " " + key + ">");
  return *found;
}

std::vector<std::string> texts_of(const XmlElement& root) {
  std::vector<std::string> out;
  for (const auto* t : root.find_all("text")) out.push_back(t->text);
  return out;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// Two methods over two scenes and their mean; "cvf" reaches the axis's top (1) in scene b.
BarChart two_methods() {
  BarChart c;
  c.title = R"(MSE <per> scene & "method")";
  c.value_label = "MSE";
  c.groups = {"scene a", "scene b", "mean"};
  c.series = {{"cvf", {0.5, 1.0, 0.75}, {}}, {"direct<1>", {std::nullopt, 0.25, 0.25}, {}}};
  c.separator_before = 2;
  return c;
}

TEST(SvgText, EscapesMarkupAndDropsForbiddenControls) {
  EXPECT_EQ(xml_escape(R"(a<b & "c" 'd'>)"), "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;");
  EXPECT_EQ(xml_escape("tab\there\x01"), "tab\there?");
  EXPECT_EQ(xml_escape("caf\xc3\xa9"), "caf\xc3\xa9");  // UTF-8 passes through
}

TEST(SvgText, NumbersAreShortDotDecimalAndAlwaysValid) {
  EXPECT_EQ(svg_number(1.0), "1");
  EXPECT_EQ(svg_number(12.5), "12.5");
  EXPECT_EQ(svg_number(-3.25), "-3.25");
  EXPECT_EQ(svg_number(1.0 / 3.0), "0.33");
  EXPECT_EQ(svg_number(-0.001), "0");
  EXPECT_EQ(svg_number(1e6), "1000000");
  EXPECT_EQ(svg_number(std::numeric_limits<double>::quiet_NaN()), "0");
  EXPECT_EQ(value_label(0.000123456789, 6), "0.000123457");
  EXPECT_EQ(value_label(1.5e-6, 3), "1.5e-06");
  EXPECT_EQ(value_label(0.25, 3), "0.25");
}

TEST(BarChart, AxisTopIsOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(value_axis_top(1.0), 1.0);
  EXPECT_DOUBLE_EQ(value_axis_top(0.0023), 0.005);
  EXPECT_DOUBLE_EQ(value_axis_top(0.0018), 0.002);
  EXPECT_DOUBLE_EQ(value_axis_top(3.0), 5.0);
  EXPECT_DOUBLE_EQ(value_axis_top(7.0), 10.0);
  EXPECT_DOUBLE_EQ(value_axis_top(0.0), 1.0);
  EXPECT_DOUBLE_EQ(value_axis_top(std::numeric_limits<double>::infinity()), 1.0);
}

TEST(BarChart, IsWellFormedSvgWithEveryBarLabelAndLegend) {
  const auto svg = bar_chart_svg(two_methods());
  const XmlElement root = XmlReader::parse(svg);
  EXPECT_EQ(root.name, "svg");
  EXPECT_EQ(root.attr("xmlns"), "http://www.w3.org/2000/svg");
  // The title survives the escaping unchanged, as the document's name and as visible text.
  ASSERT_FALSE(root.children.empty());
  EXPECT_EQ(root.children[0].name, "title");
  EXPECT_EQ(root.children[0].text, two_methods().title);
  const auto texts = texts_of(root);
  EXPECT_TRUE(contains(texts, two_methods().title));
  EXPECT_EQ(svg.find("<per>"), std::string::npos);

  // One bar per value given, in its series' group; the absent one is not drawn.
  const auto& cvf = only(root, "g", "data-name", "cvf");
  const auto& direct = only(root, "g", "data-name", "direct<1>");
  EXPECT_EQ(cvf.find_all("rect").size(), 3U);
  EXPECT_EQ(direct.find_all("rect").size(), 2U);
  EXPECT_EQ(direct.find_all("title")[0]->text, "direct<1>, scene b: 0.25");
  EXPECT_EQ(root.find_all("g").size(), 2U);

  // Axis: its name, ticks at quarters of its top, the groups' names; the legend's names.
  for (const char* t :
       {"MSE", "0", "0.25", "0.5", "0.75", "1", "scene a", "scene b", "mean", "cvf", "direct<1>"})
    EXPECT_TRUE(contains(texts, t)) << t;
  EXPECT_EQ(root.find_all("line").size() - 2 /* axes */ - 1 /* separator */, 5U /* ticks */ + 4U);
}

TEST(BarChart, ValuesMapOntoThePlotArea) {
  BarChartLayout layout;
  layout.min_plot_width = 0;  // the groups alone set the width: no centring slack
  const XmlElement root = XmlReader::parse(bar_chart_svg(two_methods(), layout));
  const Box plot = box_of(only(root, "rect", "class", "plot-area"));
  EXPECT_NEAR(plot.h, layout.plot_height, 0.01);
  EXPECT_NEAR(plot.w, 3 * (2 * layout.bar_width + layout.group_gap), 0.01);

  const auto cvf = only(root, "g", "data-name", "cvf").find_all("rect");
  const auto direct = only(root, "g", "data-name", "direct<1>").find_all("rect");
  const Box first = box_of(*cvf[0]), top = box_of(*cvf[1]), last = box_of(*direct[1]);
  // The first bar starts half a gap from the plot's left edge, the last ends half a gap from
  // its right; every bar stands on the bottom edge.
  EXPECT_NEAR(first.x, plot.x + layout.group_gap / 2, 0.011);
  EXPECT_NEAR(last.x + last.w, plot.x + plot.w - layout.group_gap / 2, 0.011);
  for (const auto* r : root.find_all("rect")) {
    if (r->attributes.contains("class")) continue;  // background, plot area, legend
    const Box b = box_of(*r);
    EXPECT_NEAR(b.y + b.h, plot.y + plot.h, 0.011);
    EXPECT_GE(b.x, plot.x);
    EXPECT_LE(b.x + b.w, plot.x + plot.w + 0.011);
  }
  // The largest value reaches the top edge (the axis top is 1); the rest in proportion.
  EXPECT_NEAR(top.y, plot.y, 0.011);
  EXPECT_NEAR(first.h, plot.h * 0.5, 0.011);
  EXPECT_NEAR(last.h, plot.h * 0.25, 0.011);
  // Bars of one group touch, in series order.
  EXPECT_NEAR(box_of(*direct[0]).x, box_of(*cvf[1]).x + layout.bar_width, 0.011);
}

TEST(BarChart, SkipsWhatCannotBeDrawn) {
  BarChart c = two_methods();
  c.series[0].values = {std::numeric_limits<double>::quiet_NaN(),
                        std::numeric_limits<double>::infinity(), -1.0};
  c.series[1].values = {std::nullopt, std::nullopt, std::nullopt};
  EXPECT_TRUE(has_bars(c));  // -1 is a value, drawn as 0
  const XmlElement root = XmlReader::parse(bar_chart_svg(c));
  const auto bars = only(root, "g", "data-name", "cvf").find_all("rect");
  ASSERT_EQ(bars.size(), 1U);
  EXPECT_NEAR(box_of(*bars[0]).h, 0.0, 0.011);

  c.series[0].values = {std::nullopt, std::numeric_limits<double>::quiet_NaN(), std::nullopt};
  EXPECT_FALSE(has_bars(c));
  EXPECT_NO_THROW(XmlReader::parse(bar_chart_svg(c)));
}

TEST(BarChart, LongGroupNamesAreSlantedAndStayOnTheCanvas) {
  BarChart c = two_methods();
  c.groups[0] = "middlebury_2014_adirondack_perfect";
  const XmlElement root = XmlReader::parse(bar_chart_svg(c));
  const XmlElement* found = nullptr;
  for (const auto* t : root.find_all("text"))
    if (t->text == c.groups[0]) found = t;
  ASSERT_NE(found, nullptr);
  const XmlElement& label = *found;
  EXPECT_TRUE(label.attr("transform").starts_with("rotate(-35 ")) << label.attr("transform");
  // At about 0.6 em per character (11 px), the slanted name ends at (x, y) and reaches
  // left by its length's cosine and down by its sine: inside the canvas both ways.
  const double length = 0.6 * 11 * static_cast<double>(c.groups[0].size());
  const double x = std::stod(label.attr("x")), y = std::stod(label.attr("y"));
  EXPECT_GE(x - length * std::cos(35 * std::numbers::pi / 180), 0.0);
  EXPECT_LE(y + length * std::sin(35 * std::numbers::pi / 180), std::stod(root.attr("height")));
}

TEST(BarChart, EverySeriesHasItsOwnColour) {
  BarChart c = two_methods();
  c.series.clear();
  for (int m = 0; m < 21; ++m)
    c.series.push_back({"method" + std::to_string(m), {1.0, 2.0, 3.0}, {}});
  const XmlElement root = XmlReader::parse(bar_chart_svg(c));
  std::set<std::string> fills;
  for (const auto* r : root.find_all("rect"))
    if (r->attributes.contains("class") && r->attr("class") == "legend-swatch")
      fills.insert(r->attr("fill"));
  EXPECT_EQ(fills.size(), 21U);
  for (const auto* g : root.find_all("g"))  // a bar's colour is its legend swatch's
    EXPECT_TRUE(fills.contains(g->find_all("rect").at(0)->attr("fill")));
}

// A process-wide locale whose decimal point is a comma (as de_DE's is) must not reach the
// numbers: they are written by std::to_chars, which knows no locale.
TEST(BarChart, NumbersIgnoreTheGlobalLocale) {
  struct CommaDecimal : std::numpunct<char> {
    char do_decimal_point() const override { return ','; }
    char do_thousands_sep() const override { return '.'; }
    std::string do_grouping() const override { return "\3"; }
  };
  const std::locale before =
      std::locale::global(std::locale(std::locale::classic(), new CommaDecimal));
  const auto svg = bar_chart_svg(two_methods());
  std::locale::global(before);
  const XmlElement root = XmlReader::parse(svg);
  const Box plot = box_of(only(root, "rect", "class", "plot-area"));
  EXPECT_NEAR(plot.h, BarChartLayout{}.plot_height, 0.01);
  EXPECT_TRUE(contains(texts_of(root), "0.25"));
  EXPECT_EQ(svg.find("0,25"), std::string::npos);
}

}  // namespace
}  // namespace probeless::eval
