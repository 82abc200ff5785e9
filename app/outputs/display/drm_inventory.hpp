#pragma once
// What the machine offers the tethered display, for `probeless devices`: each KMS card, its
// connectors, whether something is plugged in, and the modes it offers. Read-only: no mode
// is set; a card that cannot be read is listed with the reason.
#include <filesystem>
#include <string>
#include <vector>

#include "app/outputs/display/display_mode.hpp"

namespace probeless::display {

struct ConnectorInventory {
  ConnectorInfo info;
  int width_mm = 0, height_mm = 0;  // the sink's size from its EDID, 0 when unknown
  std::vector<ModeInfo> modes;      // the kernel's order, the best first
};

struct CardInventory {
  std::filesystem::path path;
  std::string driver;  // "virtio_gpu", "vc4"; empty when the card could not be read
  std::string error;   // why it could not be read
  std::vector<ConnectorInventory> connectors;
};

std::vector<CardInventory> list_displays(const std::filesystem::path& dri_dir = "/dev/dri");

}  // namespace probeless::display
