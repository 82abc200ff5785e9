#pragma once
// One error type for malformed text (configs, calibrations, manifests): it names the source
// and the line, so the CLI can print it as it is.
#include <stdexcept>
#include <string>

namespace probeless {

class ParseError : public std::runtime_error {
 public:
  ParseError(std::string source, int line, const std::string& what)
      : std::runtime_error(format(source, line, what)), source_(std::move(source)), line_(line) {}
  const std::string& source() const { return source_; }
  int line() const { return line_; }  // 1-based; 0 when the error is not tied to a line

 private:
  // Appends piecewise: GCC 12 warns (-Wrestrict, a false positive) on chained operator+.
  static std::string format(const std::string& source, int line, const std::string& what) {
    std::string text = source;
    if (line > 0) text.append(":").append(std::to_string(line));
    text.append(": ").append(what);
    return text;
  }
  std::string source_;
  int line_;
};

}  // namespace probeless
