#pragma once
// What GPIO chips this machine has, for `probeless devices` and the board bring-up: each
// /dev/gpiochipN with its label and line count, through libgpiod 1.6 (the character device;
// sysfs GPIO is deprecated). The trigger and strobe configs name a chip by any of these.
#include <filesystem>
#include <string>
#include <vector>

namespace probeless {

struct GpioChipInfo {
  std::string path;   // /dev/gpiochip0
  std::string name;   // gpiochip0
  std::string label;  // the driver's (pinctrl-rp1 on a Pi 5, the configfs label on gpio-sim)
  unsigned lines = 0;
  unsigned used = 0;  // lines a consumer has requested (this process or another)
  std::string error;  // set when the chip could not be opened (permissions, not a GPIO chip)
};

// Every gpiochip* in dev_dir, in number order; empty when there is none.
std::vector<GpioChipInfo> list_gpio_chips(const std::filesystem::path& dev_dir = "/dev");

}  // namespace probeless
