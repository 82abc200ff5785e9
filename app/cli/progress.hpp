#pragma once
// A one-line progress bar on stderr for long commands (record, eval, bench). It draws only
// when stderr is a terminal, so logs, pipes, journald and CI output stay clean; it redraws at
// most ten times a second. One thread updates it.
#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

namespace probeless::cli {

class ProgressBar {
 public:
  // total <= 0: unknown total (count and rate only).
  ProgressBar(std::string label, std::int64_t total);
  ProgressBar(std::string label, std::int64_t total, bool enabled);
  ~ProgressBar();  // ends the line if it was drawn
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // `detail` is shown after the numbers ("fisheye 120").
  void update(std::int64_t done, std::string_view detail = {});
  // Draws the final state and ends the line.
  void finish();
  bool enabled() const { return enabled_; }

  // The line for `done` of `total` after `elapsed_s` seconds, at most `width` columns.
  static std::string render(std::string_view label, std::int64_t done, std::int64_t total,
                            double elapsed_s, std::string_view detail, int width);

 private:
  void draw(bool force);
  std::string label_;
  std::int64_t total_;
  bool enabled_;
  bool drawn_ = false;
  std::int64_t done_ = 0;
  std::string detail_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_{};
};

}  // namespace probeless::cli
