#include "drivers/trigger/gpio_trigger.hpp"

#include <stdexcept>
#include <system_error>
#include <thread>

namespace probeless {

GpioTrigger::GpioTrigger(GpioTriggerConfig config) : config_(std::move(config)) {
  try {
    chip_ = gpiod::chip(config_.chip, gpiod::chip::OPEN_LOOKUP);
  } catch (const std::exception& e) {
    throw std::runtime_error("gpio trigger: cannot open GPIO chip '" + config_.chip +
                             "': " + e.what());
  }
  if (config_.line >= chip_.num_lines())
    throw std::runtime_error("gpio trigger: " + chip_.name() + " has " +
                             std::to_string(chip_.num_lines()) + " lines, no line " +
                             std::to_string(config_.line));
  try {
    line_ = chip_.get_line(config_.line);
    gpiod::line_request request;
    request.consumer = config_.consumer;
    request.request_type = gpiod::line_request::DIRECTION_OUTPUT;
    if (config_.active_low) request.flags = gpiod::line_request::FLAG_ACTIVE_LOW;
    line_.request(request, 0);  // inactive until the first frame
  } catch (const std::exception& e) {
    // EBUSY: name the holder (a strobe, another service, a shell's gpioset).
    const std::string holder = line_ && line_.is_used() && !line_.consumer().empty()
                                   ? " (held by '" + line_.consumer() + "')"
                                   : "";
    throw std::runtime_error("gpio trigger: cannot drive " + name() + holder + ": " + e.what());
  }
}

GpioTrigger::~GpioTrigger() {
  try {
    if (line_ && line_.is_requested()) {
      line_.set_value(0);
      line_.release();
    }
  } catch (const std::exception&) {
    // The chip went away (unplugged board): nothing left to release.
  }
}

TimestampNs GpioTrigger::fire(const ExposureStamp& /*exposure*/) {
  try {
    line_.set_value(1);
    const TimestampNs edge = monotonic_now_ns();
    std::this_thread::sleep_for(config_.pulse_width);
    line_.set_value(0);
    return edge;
  } catch (const std::system_error& e) {
    throw std::runtime_error("gpio trigger: " + name() + ": " + e.what());
  }
}

std::string GpioTrigger::name() const {
  return config_.chip + " line " + std::to_string(config_.line);
}

}  // namespace probeless
