#include "lab/eval/bar_chart.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>

#include "lab/eval/svg_document.hpp"

namespace probeless::eval {
namespace {

// Matplotlib's default colours, familiar from most published plots.
constexpr std::array<std::uint32_t, 10> kPalette = {0x1f77b4, 0xff7f0e, 0x2ca02c, 0xd62728,
                                                    0x9467bd, 0x8c564b, 0xe377c2, 0x7f7f7f,
                                                    0xbcbd22, 0x17becf};
constexpr int kTicks = 4;  // intervals on the value axis: 0, 1/4, ..., 1 of its top

constexpr double kTitleSize = 15, kLabelSize = 12, kTickSize = 11;
constexpr double kMargin = 12;
constexpr double kLegendRow = 18, kSwatch = 12;
constexpr double kSlantDeg = 35;  // group names slanted by this when they would overlap

constexpr TextStyle kTitleStyle{kTitleSize, TextAnchor::start, true, 0};
constexpr TextStyle kTickStyle{kTickSize, TextAnchor::end, false, 0};
constexpr TextStyle kAxisNameStyle{kLabelSize, TextAnchor::middle, false, -90};
constexpr TextStyle kLegendStyle{kLabelSize, TextAnchor::start, false, 0};
constexpr TextStyle kGroupStyle{kTickSize, TextAnchor::middle, false, 0};
constexpr TextStyle kSlantedGroupStyle{kTickSize, TextAnchor::end, false, -kSlantDeg};

// No font metrics without a font: about 0.6 em per character in DejaVu Sans and Verdana,
// enough to keep labels clear of each other.
double estimated_text_width(const std::string& s, double size) {
  return 0.6 * size * static_cast<double>(s.size());
}

double widest(const std::vector<std::string>& texts, double size) {
  double w = 0;
  for (const auto& t : texts) w = std::max(w, estimated_text_width(t, size));
  return w;
}

double largest_value(const BarChart& chart) {
  double v = 0;
  for (const auto& s : chart.series)
    for (const auto& x : s.values)
      if (x && std::isfinite(*x)) v = std::max(v, *x);
  return v;
}

// Where everything goes, in user units: the plot area, each group's share of its width,
// the legend's column and the canvas.
struct Geometry {
  double plot_x = 0, plot_y = 0, plot_w = 0, plot_h = 0;
  double group_w = 0, bars_w = 0;  // a group's share; its bars side by side
  bool slanted = false;            // group names slanted under the axis
  double legend_x = 0, width = 0, height = 0;

  double bar_x(std::size_t group, std::size_t series, double bar_width) const {
    return plot_x + static_cast<double>(group) * group_w + (group_w - bars_w) / 2 +
           bar_width * static_cast<double>(series);
  }
};

Geometry place(const BarChart& chart, const BarChartLayout& layout,
               const std::vector<std::string>& ticks) {
  Geometry g;
  const auto groups = static_cast<double>(std::max<std::size_t>(chart.groups.size(), 1));
  g.bars_w = layout.bar_width * static_cast<double>(chart.series.size());
  g.plot_w = std::max(layout.min_plot_width, groups * (g.bars_w + layout.group_gap));
  g.plot_h = layout.plot_height;
  g.group_w = g.plot_w / groups;
  const double names_w = widest(chart.groups, kTickSize);
  g.slanted = names_w > g.group_w - 4;
  const double slant = kSlantDeg * std::numbers::pi / 180;
  const double names_h = g.slanted ? names_w * std::sin(slant) + kTickSize : kTickSize;
  // Room on the left for the axis's name and tick labels, and for the first group's name,
  // which reaches left of its group when slanted.
  g.plot_x =
      std::max(kMargin + kLabelSize + 8 + widest(ticks, kTickSize) + 8,
               kMargin + (g.slanted ? names_w * std::cos(slant) : names_w / 2) - g.group_w / 2);
  g.plot_y = kMargin + kTitleSize + 14;
  g.legend_x = g.plot_x + g.plot_w + 16;
  std::vector<std::string> series_names;
  for (const auto& s : chart.series) series_names.push_back(s.name);
  g.width = g.legend_x + kSwatch + 6 + widest(series_names, kLabelSize) + kMargin;
  g.height = std::max(g.plot_y + g.plot_h + 10 + names_h + kMargin,
                      g.plot_y + kLegendRow * static_cast<double>(chart.series.size()) + kMargin);
  return g;
}

// Grid lines and labels at quarters of the axis's top, the axis's name along it.
void draw_value_axis(SvgDocument& svg, const Geometry& g, const std::vector<std::string>& ticks,
                     const std::string& name) {
  for (std::size_t t = 0; t < ticks.size(); ++t) {
    const double y = g.plot_y + g.plot_h - g.plot_h * static_cast<double>(t) / kTicks;
    if (t > 0) svg.line(g.plot_x, y, g.plot_x + g.plot_w, y, "#dddddd", "grid");
    svg.line(g.plot_x - 4, y, g.plot_x, y, "#000000", "tick");
    svg.text(g.plot_x - 7, y + kTickSize * 0.35, ticks[t], kTickStyle);
  }
  svg.text(kMargin + kLabelSize, g.plot_y + g.plot_h / 2, name, kAxisNameStyle);
}

}  // namespace

std::string series_colour(std::size_t n, bool paler) {
  const std::uint32_t rgb = kPalette[n % kPalette.size()];
  const auto round = n / kPalette.size() + (paler ? 1 : 0);
  const double pale = 1.0 - std::pow(0.5, static_cast<double>(round));
  const auto channel = [&](int shift) {
    const double c = static_cast<double>((rgb >> shift) & 0xffU);
    return static_cast<unsigned>(std::lround(c + (255.0 - c) * pale));
  };
  std::array<char, 8> hex{};
  std::snprintf(hex.data(), hex.size(), "#%02x%02x%02x", channel(16), channel(8), channel(0));
  return hex.data();
}

double value_axis_top(double largest) {
  if (!(largest > 0) || !std::isfinite(largest)) return 1;
  const double p = std::pow(10.0, std::floor(std::log10(largest)));
  for (const double step : {1.0, 2.0, 5.0})
    if (largest <= step * p) return step * p;
  return 10 * p;
}

bool has_bars(const BarChart& chart) {
  for (const auto& s : chart.series)
    for (const auto& x : s.values)
      if (x && std::isfinite(*x)) return true;
  return false;
}

std::string bar_chart_svg(const BarChart& chart, const BarChartLayout& layout) {
  const double top_value = value_axis_top(largest_value(chart));
  std::vector<std::string> ticks;
  for (int t = 0; t <= kTicks; ++t) ticks.push_back(value_label(top_value * t / kTicks, 3));
  const Geometry g = place(chart, layout, ticks);
  const double bottom = g.plot_y + g.plot_h;

  SvgDocument svg(g.width, g.height, chart.title);
  svg.text(g.plot_x, kMargin + kTitleSize, chart.title, kTitleStyle);
  svg.rect(g.plot_x, g.plot_y, g.plot_w, g.plot_h, "#ffffff", {}, "plot-area");
  draw_value_axis(svg, g, ticks, chart.value_label);

  for (std::size_t m = 0; m < chart.series.size(); ++m) {
    const auto& s = chart.series[m];
    const std::string colour = s.colour.empty() ? series_colour(m) : s.colour;
    svg.begin_group("series", s.name);
    for (std::size_t k = 0; k < s.values.size() && k < chart.groups.size(); ++k) {
      if (!s.values[k] || !std::isfinite(*s.values[k])) continue;
      const double v = *s.values[k];
      const double y = bottom - g.plot_h * std::clamp(v / top_value, 0.0, 1.0);
      svg.rect(g.bar_x(k, m, layout.bar_width), y, layout.bar_width, bottom - y, colour,
               s.name + ", " + chart.groups[k] + ": " + value_label(v, 6));
    }
    svg.end_group();
    const double ly = g.plot_y + kLegendRow * static_cast<double>(m);
    svg.rect(g.legend_x, ly, kSwatch, kSwatch, colour, {}, "legend-swatch");
    svg.text(g.legend_x + kSwatch + 6, ly + kSwatch - 1, s.name, kLegendStyle);
  }

  if (chart.separator_before && *chart.separator_before > 0 &&
      *chart.separator_before < chart.groups.size()) {
    const double x = g.plot_x + static_cast<double>(*chart.separator_before) * g.group_w;
    svg.line(x, g.plot_y, x, bottom, "#999999", "separator");
  }
  // The axes after the bars, over their edges; the group names under them.
  svg.line(g.plot_x, bottom, g.plot_x + g.plot_w, bottom, "#000000", "axis");
  svg.line(g.plot_x, g.plot_y, g.plot_x, bottom, "#000000", "axis");
  for (std::size_t k = 0; k < chart.groups.size(); ++k) {
    const double cx = g.plot_x + (static_cast<double>(k) + 0.5) * g.group_w;
    svg.text(cx, bottom + 6 + kTickSize, chart.groups[k],
             g.slanted ? kSlantedGroupStyle : kGroupStyle);
  }
  return std::move(svg).finish();
}

}  // namespace probeless::eval
