#pragma once
// Grouped bar charts as SVG (lab/eval/svg_document.hpp): one group of bars per scene, one
// bar per series (method) in each, in the manner of the thesis's Fig. 3.5 and 3.7. A value
// axis from 0 with ticks and grid lines, group names under the bars (slanted when they do
// not fit), a legend of the series on the right, each bar's value in its tooltip.
#include <optional>
#include <string>
#include <vector>

namespace probeless::eval {

struct BarSeries {
  std::string name;
  std::vector<std::optional<double>> values;  // one per group; absent = no bar
  std::string colour;                         // "#rrggbb"; empty = series_colour(its index)
};

struct BarChart {
  std::string title;
  std::string value_label;  // the vertical axis's name
  std::vector<std::string> groups;
  std::vector<BarSeries> series;
  // Group index before which a thin rule separates the rest (e.g. the mean); none if absent.
  std::optional<std::size_t> separator_before;
};

// Sizes in user units (px). The plot area is `plot_height` high and as wide as the groups
// need (at least `min_plot_width`); the groups divide it evenly, left to right, and each
// group's bars touch one another, centred in its share.
struct BarChartLayout {
  double bar_width = 12;
  double group_gap = 16;  // at least, between the last bar of a group and the next's first
  double plot_height = 240;
  double min_plot_width = 240;
};

// The axis's top: the smallest 1, 2 or 5 times a power of ten at or above `largest` (1 when
// `largest` is not above 0), so that the ticks at quarters are short numbers.
double value_axis_top(double largest);

// The n-th colour of matplotlib's default cycle ("tab10"), half way to white when `paler`
// (for a variant of series n, e.g. a method and its stabilised version). The cycle has ten
// colours and then repeats paler, so colour n + 10 is colour n paler.
std::string series_colour(std::size_t n, bool paler = false);

// True when some series has a finite value to draw.
bool has_bars(const BarChart& chart);

// The whole SVG document. The plot area is the <rect class="plot-area">, each series a
// <g class="series" data-name="NAME"> of one <rect> per drawn value. Negative values are drawn
// as 0 and non-finite ones not at all.
std::string bar_chart_svg(const BarChart& chart, const BarChartLayout& layout = {});

}  // namespace probeless::eval
