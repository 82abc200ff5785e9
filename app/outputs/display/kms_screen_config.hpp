#pragma once
// Which screen KmsScreen (kms_screen.hpp) opens, apart from it: the service config holds
// one without pulling in the DRM, GBM and EGL headers.
#include <chrono>
#include <filesystem>
#include <string>

namespace probeless::display {

struct KmsScreenConfig {
  std::string card;       // "card0" or a path; empty: the first card with a usable connector
  std::string connector;  // "HDMI-A-1"; empty: the first connected
  std::string mode;       // "1920x1080@60"; empty: the connector's preferred mode
  std::filesystem::path dri_dir = "/dev/dri";
  // A flip normally completes within one refresh (17 ms at 60 Hz); this bounds a stuck one.
  std::chrono::milliseconds flip_timeout{500};
};

}  // namespace probeless::display
