#pragma once
// The "What this config needs" section of `probeless devices [--board NAME]`: for each thing
// the resolved config uses (the RGB-D sensor, the fisheye device, the calibration file, GPIO
// chips, the display), whether it is there and usable by this user, and what to do if not.
#include <ostream>
#include <string>
#include <vector>

#include "app/pipeline/service_config.hpp"

namespace probeless::cli {

struct Need {
  std::string what;  // "fisheye /dev/video0", "calibration /etc/probeless/calibration.toml"
  bool ok = false;
  std::string detail;  // what was found, or what is missing and how to fix it
};

// Looks at the machine (files, device nodes, USB, OpenNI2) without opening the streams.
std::vector<Need> check_needs(const ServiceConfig& config);
void print_needs(std::ostream& out, const ServiceConfig& config);

}  // namespace probeless::cli
