#pragma once
// OpenNI2 as a process-wide resource: openni::OpenNI::initialize() loads the drivers
// (Debian: /usr/lib/<triplet>/OpenNI2/Drivers, beside libOpenNI2; settings in
// /etc/openni2/OpenNI.ini) and shutdown() unloads them for everybody. A source, the devices
// command and the tests each hold an OpenniRuntime; the last one to let go shuts OpenNI down.
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace probeless::openni2 {

// OpenNI2 could not start, or a device or recording cannot be used as configured.
class OpenniError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class OpenniRuntime {
 public:
  // Initialises OpenNI2 on first use. Throws OpenniError with OpenNI's own message.
  static std::shared_ptr<OpenniRuntime> acquire();
  ~OpenniRuntime();
  OpenniRuntime(const OpenniRuntime&) = delete;
  OpenniRuntime& operator=(const OpenniRuntime&) = delete;

 private:
  OpenniRuntime();
};

// OpenNI's last error text, trimmed ("" when it has none).
std::string openni_error_text();

struct VideoModeInfo {
  std::string sensor;  // "depth", "colour", "ir"
  int width = 0, height = 0, fps = 0;
  std::string pixel_format;  // "DEPTH_1_MM", "RGB888", ...
};

struct DeviceListing {
  std::string uri, vendor, name;
  std::uint16_t usb_vendor = 0, usb_product = 0;
  std::vector<VideoModeInfo> modes;  // empty when the device could not be opened to ask
  std::string error;                 // why the modes are missing
};

// Every device OpenNI2 enumerates, each opened briefly for its video modes (a device in use
// by another process lists without them).
std::vector<DeviceListing> list_openni_devices();

const char* pixel_format_name(int oni_pixel_format);
std::string describe(const VideoModeInfo& mode);  // "640x480@30 RGB888"

}  // namespace probeless::openni2
