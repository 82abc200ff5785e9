#include "app/cli/progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>

namespace probeless::cli {
namespace {

constexpr auto kRedrawInterval = std::chrono::milliseconds(100);

int terminal_width() {
  winsize ws{};
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) return ws.ws_col;
  return 80;
}

std::string clock_text(double seconds) {
  const auto s = static_cast<long long>(std::llround(std::max(0.0, seconds)));
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

}  // namespace

ProgressBar::ProgressBar(std::string label, std::int64_t total)
    : ProgressBar(std::move(label), total, isatty(STDERR_FILENO) == 1) {}

ProgressBar::ProgressBar(std::string label, std::int64_t total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() {
  if (drawn_) std::fputc('\n', stderr);
}

std::string ProgressBar::render(std::string_view label, std::int64_t done, std::int64_t total,
                                double elapsed_s, std::string_view detail, int width) {
  const double rate = elapsed_s > 0 ? static_cast<double>(done) / elapsed_s : 0.0;
  std::string numbers;
  if (total > 0) {
    const double fraction = std::clamp(static_cast<double>(done) / static_cast<double>(total), 0.0, 1.0);
    numbers = fmt::format(" {}/{} {:3.0f}% {:.1f}/s", done, total, 100 * fraction, rate);
    if (done < total && rate > 0) {
      numbers += fmt::format(" ETA {}", clock_text(static_cast<double>(total - done) / rate));
    } else {
      numbers += fmt::format(" {}", clock_text(elapsed_s));
    }
  } else {
    numbers = fmt::format(" {} {:.1f}/s {}", done, rate, clock_text(elapsed_s));
  }
  if (!detail.empty()) numbers += fmt::format("  {}", detail);

  std::string line(label);
  const int room = width - 1 - static_cast<int>(line.size() + numbers.size()) - 3;
  if (total > 0 && room >= 10) {
    const int bar = std::min(room, 40);
    const double fraction = std::clamp(static_cast<double>(done) / static_cast<double>(total), 0.0, 1.0);
    const int filled = static_cast<int>(fraction * bar);
    line += " [";
    line.append(static_cast<std::size_t>(filled), '#');
    line.append(static_cast<std::size_t>(bar - filled), '.');
    line += ']';
  }
  line += numbers;
  if (width > 0 && line.size() > static_cast<std::size_t>(width - 1)) {
    line.resize(static_cast<std::size_t>(std::max(0, width - 1)));
  }
  return line;
}

void ProgressBar::update(std::int64_t done, std::string_view detail) {
  done_ = done;
  detail_ = detail;
  draw(false);
}

void ProgressBar::finish() {
  draw(true);
  if (drawn_) {
    std::fputc('\n', stderr);
    drawn_ = false;
  }
  enabled_ = false;  // nothing more after the final line
}

void ProgressBar::draw(bool force) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && drawn_ && now - last_draw_ < kRedrawInterval) return;
  last_draw_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const std::string line = render(label_, done_, total_, elapsed, detail_, terminal_width());
  // Carriage return, the line, and "erase to end of line" for a shorter redraw.
  std::fprintf(stderr, "\r%s\x1b[K", line.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

}  // namespace probeless::cli
