#include "drivers/trigger/gpio_chips.hpp"

#include <algorithm>
#include <cstdlib>
#include <gpiod.hpp>
#include <system_error>

namespace probeless {
namespace {

// gpiochip10 after gpiochip9.
unsigned long chip_number(const std::string& name) {
  return std::strtoul(name.c_str() + std::string("gpiochip").size(), nullptr, 10);
}

}  // namespace

std::vector<GpioChipInfo> list_gpio_chips(const std::filesystem::path& dev_dir) {
  std::vector<GpioChipInfo> chips;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dev_dir, ec)) {
    const std::string file = entry.path().filename().string();
    if (file.rfind("gpiochip", 0) != 0) continue;
    GpioChipInfo info;
    info.path = entry.path().string();
    info.name = file;
    try {
      gpiod::chip chip(info.path, gpiod::chip::OPEN_BY_PATH);
      info.name = chip.name();
      info.label = chip.label();
      info.lines = chip.num_lines();
      for (unsigned i = 0; i < info.lines; ++i)
        if (chip.get_line(i).is_used()) ++info.used;
    } catch (const std::exception& e) {
      info.error = e.what();
    }
    chips.push_back(std::move(info));
  }
  std::sort(chips.begin(), chips.end(), [](const GpioChipInfo& a, const GpioChipInfo& b) {
    return chip_number(std::filesystem::path(a.path).filename().string()) <
           chip_number(std::filesystem::path(b.path).filename().string());
  });
  return chips;
}

}  // namespace probeless
