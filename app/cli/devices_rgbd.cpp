#include "app/cli/devices_rgbd.hpp"

#include <fmt/format.h>

#include <map>

#include "drivers/openni2/openni2_runtime.hpp"
#include "drivers/usb/usb_hotplug.hpp"

namespace probeless::cli {

void print_rgbd_sensors(std::ostream& out, const std::vector<std::uint16_t>& usb_vendors) {
  out << "RGB-D sensors\n";
  try {
    const auto devices = openni2::list_openni_devices();
    if (devices.empty())
      out << "  OpenNI2: no device (source spec \"openni2:\" would wait for one)\n";
    for (const auto& d : devices) {
      out << fmt::format("  OpenNI2 {} '{}' by {} (USB {:04x}:{:04x})\n", d.uri, d.name, d.vendor,
                         d.usb_vendor, d.usb_product);
      if (!d.error.empty()) out << fmt::format("      modes unknown: {}\n", d.error);
      // One line per sensor: its modes side by side.
      std::map<std::string, std::string> by_sensor;
      for (const auto& m : d.modes)
        by_sensor[m.sensor] += (by_sensor[m.sensor].empty() ? "" : ", ") + openni2::describe(m);
      for (const auto& [sensor, modes] : by_sensor)
        out << fmt::format("      {}: {}\n", sensor, modes);
    }
  } catch (const openni2::OpenniError& e) {
    out << fmt::format("  OpenNI2: {}\n", e.what());
  }
  std::string vendors;
  for (auto v : usb_vendors) vendors += fmt::format("{}{:04x}", vendors.empty() ? "" : ":", v);
  try {
    const auto usb = usb::list_usb_devices(usb_vendors);
    out << fmt::format("  USB (vendors {}): {}\n", vendors,
                       usb.empty() ? "none present" : std::to_string(usb.size()) + " present");
    for (const auto& id : usb) out << fmt::format("      {}\n", usb::describe(id));
  } catch (const usb::UsbError& e) {
    out << fmt::format("  USB (vendors {}): {}\n", vendors, e.what());
  }
}

}  // namespace probeless::cli
