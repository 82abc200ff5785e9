#pragma once
// The exposure trigger on a GPIO line, through libgpiod 1.6's C++ bindings (gpiod.hpp, the
// character device /dev/gpiochipN; sysfs GPIO is deprecated). Each fire() drives the line
// active for pulse_width, then inactive. The hardware test runs against gpio-sim in a VM
// (issue #7); here the class opens a real chip or fails with a message naming it.
#include <chrono>
#include <gpiod.hpp>
#include <string>

#include "drivers/trigger/exposure_trigger.hpp"

namespace probeless {

struct GpioTriggerConfig {
  std::string chip = "gpiochip0";  // name, path (/dev/gpiochip0), label or number
  unsigned line = 0;               // offset on the chip
  // Long enough for a sensor's trigger input to see it (the IMX296's minimum is a few
  // microseconds), short against the 20 ms frame period.
  std::chrono::microseconds pulse_width{100};
  bool active_low = false;
  std::string consumer = "probeless";
};

class GpioTrigger final : public ExposureTrigger {
 public:
  // Opens the chip and requests the line as an output, inactive. Throws std::runtime_error
  // naming the chip and line when either is missing or busy.
  explicit GpioTrigger(GpioTriggerConfig config);
  ~GpioTrigger() override;
  GpioTrigger(const GpioTrigger&) = delete;
  GpioTrigger& operator=(const GpioTrigger&) = delete;

  TimestampNs fire(const ExposureStamp& exposure) override;
  std::string name() const override;

 private:
  GpioTriggerConfig config_;
  gpiod::chip chip_;
  gpiod::line line_;
};

}  // namespace probeless
