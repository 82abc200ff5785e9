#include "lab/eval/svg_document.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <stdexcept>

namespace probeless::eval {
namespace {

const char* anchor_name(TextAnchor a) {
  switch (a) {
    case TextAnchor::middle:
      return "middle";
    case TextAnchor::end:
      return "end";
    case TextAnchor::start:
      break;
  }
  return "start";
}

// Appends the parts in order (and keeps GCC 12's -Wrestrict quiet, which misfires on chains
// of std::string operator+ at -O3).
void put(std::string& out, std::initializer_list<std::string_view> parts) {
  for (const auto part : parts) out.append(part);
}

// ` name="value"`, the value escaped.
void attribute(std::string& out, std::string_view name, std::string_view value) {
  put(out, {" ", name, "=\"", xml_escape(value), "\""});
}

void attribute(std::string& out, std::string_view name, double value) {
  put(out, {" ", name, "=\"", svg_number(value), "\""});
}

}  // namespace

std::string xml_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        // XML 1.0 has no way to write C0 controls other than tab, newline and return.
        const bool forbidden =
            static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r';
        out += forbidden ? '?' : c;
    }
  }
  return out;
}

std::string svg_number(double v) {
  if (!std::isfinite(v)) return "0";
  std::array<char, 64> buf{};
  const auto [end, ec] =
      std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::fixed, 2);
  if (ec != std::errc{}) throw std::logic_error("svg_number: coordinate out of range");
  std::string s(buf.data(), end);
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

std::string value_label(double v, int significant) {
  std::array<char, 64> buf{};
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v,
                                       std::chars_format::general, significant);
  if (ec != std::errc{}) throw std::logic_error("value_label: buffer too small");
  return {buf.data(), end};
}

SvgDocument::SvgDocument(double width, double height, std::string_view title) {
  out_ = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\"";
  out_ += " version=\"1.1\"";
  attribute(out_, "width", width);
  attribute(out_, "height", height);
  put(out_, {" viewBox=\"0 0 ", svg_number(width), " ", svg_number(height), "\""});
  out_ += " font-family=\"DejaVu Sans, Verdana, sans-serif\">\n";
  put(out_, {"<title>", xml_escape(title), "</title>\n"});
  rect(0, 0, width, height, "#ffffff", {}, "background");
}

void SvgDocument::rect(double x, double y, double width, double height, std::string_view fill,
                       std::string_view tooltip, std::string_view css_class) {
  out_ += "<rect";
  if (!css_class.empty()) attribute(out_, "class", css_class);
  attribute(out_, "x", x);
  attribute(out_, "y", y);
  attribute(out_, "width", width);
  attribute(out_, "height", height);
  attribute(out_, "fill", fill);
  if (tooltip.empty()) {
    out_ += "/>\n";
  } else {
    put(out_, {"><title>", xml_escape(tooltip), "</title></rect>\n"});
  }
}

void SvgDocument::line(double x1, double y1, double x2, double y2, std::string_view stroke,
                       std::string_view css_class) {
  out_ += "<line";
  if (!css_class.empty()) attribute(out_, "class", css_class);
  attribute(out_, "x1", x1);
  attribute(out_, "y1", y1);
  attribute(out_, "x2", x2);
  attribute(out_, "y2", y2);
  attribute(out_, "stroke", stroke);
  out_ += "/>\n";
}

void SvgDocument::text(double x, double y, std::string_view content, const TextStyle& style) {
  out_ += "<text";
  attribute(out_, "x", x);
  attribute(out_, "y", y);
  attribute(out_, "font-size", style.size);
  if (style.anchor != TextAnchor::start) attribute(out_, "text-anchor", anchor_name(style.anchor));
  if (style.bold) attribute(out_, "font-weight", "bold");
  if (style.rotate_deg != 0) {
    std::string rotation;
    put(rotation,
        {"rotate(", svg_number(style.rotate_deg), " ", svg_number(x), " ", svg_number(y), ")"});
    attribute(out_, "transform", rotation);
  }
  put(out_, {">", xml_escape(content), "</text>\n"});
}

void SvgDocument::begin_group(std::string_view css_class, std::string_view name) {
  out_ += "<g";
  attribute(out_, "class", css_class);
  attribute(out_, "data-name", name);
  out_ += ">\n";
  ++open_groups_;
}

void SvgDocument::end_group() {
  if (open_groups_ == 0) throw std::logic_error("SvgDocument: end_group without a group");
  out_ += "</g>\n";
  --open_groups_;
}

std::string SvgDocument::finish() && {
  for (; open_groups_ > 0; --open_groups_) out_ += "</g>\n";
  out_ += "</svg>\n";
  return std::move(out_);
}

}  // namespace probeless::eval
