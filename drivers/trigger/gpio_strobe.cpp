#include "drivers/trigger/gpio_strobe.hpp"

#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <stdexcept>
#include <system_error>

namespace probeless {

StrobeEdge parse_strobe_edge(std::string_view text) {
  if (text == "rising") return StrobeEdge::Rising;
  if (text == "falling") return StrobeEdge::Falling;
  if (text == "both") return StrobeEdge::Both;
  throw std::invalid_argument("strobe edge '" + std::string(text) +
                              "': expected \"rising\", \"falling\" or \"both\"");
}

std::string_view to_string(StrobeEdge edge) {
  switch (edge) {
    case StrobeEdge::Rising:
      return "rising";
    case StrobeEdge::Falling:
      return "falling";
    case StrobeEdge::Both:
      return "both";
  }
  return "?";
}

namespace {

int request_type(StrobeEdge edge) {
  switch (edge) {
    case StrobeEdge::Rising:
      return gpiod::line_request::EVENT_RISING_EDGE;
    case StrobeEdge::Falling:
      return gpiod::line_request::EVENT_FALLING_EDGE;
    case StrobeEdge::Both:
      return gpiod::line_request::EVENT_BOTH_EDGES;
  }
  return gpiod::line_request::EVENT_RISING_EDGE;
}

bool interrupted(const std::system_error& e) {
  return e.code() == std::errc::interrupted;
}

}  // namespace

GpioStrobe::GpioStrobe(GpioStrobeConfig config) : config_(std::move(config)) {
  try {
    chip_ = gpiod::chip(config_.chip, gpiod::chip::OPEN_LOOKUP);
  } catch (const std::exception& e) {
    throw std::runtime_error("gpio strobe: cannot open GPIO chip '" + config_.chip +
                             "': " + e.what());
  }
  if (config_.line >= chip_.num_lines())
    throw std::runtime_error("gpio strobe: " + config_.chip + " (" + chip_.name() + ") has " +
                             std::to_string(chip_.num_lines()) + " lines, no line " +
                             std::to_string(config_.line));
  try {
    line_ = chip_.get_line(config_.line);
    gpiod::line_request request;
    request.consumer = config_.consumer;
    request.request_type = request_type(config_.edge);
    if (config_.active_low) request.flags = gpiod::line_request::FLAG_ACTIVE_LOW;
    line_.request(request);
  } catch (const std::exception& e) {
    // EBUSY names the holder: another process (or this one) already requested the line.
    const std::string holder = line_ && line_.is_used() && !line_.consumer().empty()
                                   ? " (held by '" + line_.consumer() + "')"
                                   : "";
    throw std::runtime_error("gpio strobe: cannot watch " + name() + " for " +
                             std::string(to_string(config_.edge)) + " edges" + holder + ": " +
                             e.what());
  }
}

GpioStrobe::~GpioStrobe() {
  try {
    if (line_ && line_.is_requested()) line_.release();
  } catch (const std::exception&) {
    // The chip went away (unplugged board): nothing left to release.
  }
}

std::optional<StrobeEvent> GpioStrobe::wait(std::chrono::nanoseconds timeout) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + timeout;
  pollfd pfd{};
  pfd.fd = line_.event_get_fd();
  pfd.events = POLLIN;
  for (;;) {
    const auto left =
        std::max(std::chrono::nanoseconds(0),
                 std::chrono::duration_cast<std::chrono::nanoseconds>(deadline - Clock::now()));
    const timespec ts{static_cast<time_t>(left.count() / 1'000'000'000),
                      static_cast<long>(left.count() % 1'000'000'000)};
    const int n = ppoll(&pfd, 1, &ts, nullptr);
    if (n < 0 && errno == EINTR) continue;  // a signal: wait out the rest of the timeout
    if (n < 0)
      throw std::runtime_error("gpio strobe: " + name() +
                               ": poll: " + std::system_category().message(errno));
    if (n == 0) return std::nullopt;
    if ((pfd.revents & POLLIN) == 0)
      throw std::runtime_error("gpio strobe: " + name() + ": the chip went away");
    break;
  }
  for (;;) {
    try {
      const gpiod::line_event e = line_.event_read();
      return StrobeEvent{static_cast<TimestampNs>(e.timestamp.count()),
                         e.event_type == gpiod::line_event::RISING_EDGE};
    } catch (const std::system_error& e) {
      if (interrupted(e)) continue;
      throw std::runtime_error("gpio strobe: " + name() + ": reading an edge: " + e.what());
    }
  }
}

std::optional<StrobeEvent> GpioStrobe::latest() {
  std::optional<StrobeEvent> newest;
  while (auto e = wait(std::chrono::nanoseconds(0))) newest = e;
  return newest;
}

std::optional<StrobeEvent> stamp_with_strobe(GpioStrobe& strobe, FisheyeFrame& frame,
                                             std::chrono::nanoseconds timeout) {
  std::optional<StrobeEvent> edge = strobe.latest();
  if (!edge) edge = strobe.wait(timeout);
  if (edge) frame.timestamp_ns = edge->time_ns;
  return edge;
}

std::string GpioStrobe::name() const {
  return config_.chip + " line " + std::to_string(config_.line);
}

}  // namespace probeless
