#pragma once
#include <cstdint>
#include <ostream>
#include <vector>

namespace probeless::cli {

// The "RGB-D sensors" section of `probeless devices`: OpenNI2's devices with their video
// modes, and the USB devices of the sensor vendors (drivers/usb/usb_hotplug.hpp).
void print_rgbd_sensors(std::ostream& out, const std::vector<std::uint16_t>& usb_vendors);

}  // namespace probeless::cli
