#pragma once
// A few SVG elements written as text, for the evaluators' plots (lab/eval/bar_chart.hpp).
// Plain SVG 1.1 rather than a raster with a font of our own: any browser or image viewer
// shows it, it scales, and its text stays text (searchable, copyable, diffable). Every string
// is escaped for XML and every number written by std::to_chars, so no locale can turn a
// decimal point into a comma.
#include <string>
#include <string_view>

namespace probeless::eval {

// `text` with &, <, >, " and ' as entities and control characters XML 1.0 forbids as '?'.
std::string xml_escape(std::string_view text);

// A coordinate rounded to 1/100 of a user unit (no screen needs more), trailing zeros
// dropped; NaN and infinities as 0 so that the document stays valid.
std::string svg_number(double v);

// A measured value for people to read: `significant` digits, exponent form where shorter
// (0.0025, 1.5e-05); "nan" / "inf" as they are.
std::string value_label(double v, int significant);

enum class TextAnchor { start, middle, end };

struct TextStyle {
  double size = 12;  // px
  TextAnchor anchor = TextAnchor::start;
  bool bold = false;
  double rotate_deg = 0;  // about the text's anchor point, clockwise
};

class SvgDocument {
 public:
  // A white canvas of width x height user units (= CSS pixels), y down.
  SvgDocument(double width, double height, std::string_view title);

  // `tooltip`, when given, becomes the element's <title> (shown when hovering over it).
  void rect(double x, double y, double width, double height, std::string_view fill,
            std::string_view tooltip = {}, std::string_view css_class = {});
  void line(double x1, double y1, double x2, double y2, std::string_view stroke,
            std::string_view css_class = {});
  void text(double x, double y, std::string_view content, const TextStyle& style = {});

  // Elements between begin_group and end_group are one <g> (e.g. a data series).
  void begin_group(std::string_view css_class, std::string_view name);
  void end_group();

  // The document, closed.
  std::string finish() &&;

 private:
  std::string out_;
  int open_groups_ = 0;
};

}  // namespace probeless::eval
