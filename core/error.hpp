#pragma once
// One error type for malformed text (configs, calibrations, manifests): it names the source
// and the line, so the CLI can print it as it is.
#include <stdexcept>
#include <string>

namespace probeless {

class ParseError : public std::runtime_error {
 public:
  ParseError(std::string source, int line, const std::string& what)
      : std::runtime_error(source + (line > 0 ? ":" + std::to_string(line) : std::string()) +
                           ": " + what),
        source_(std::move(source)),
        line_(line) {}
  const std::string& source() const { return source_; }
  int line() const { return line_; }  // 1-based; 0 when the error is not tied to a line

 private:
  std::string source_;
  int line_;
};

}  // namespace probeless
