#pragma once
// What an `openni2:` source spec says (docs/drivers.md "OpenNI2 RGB-D"):
//   openni2:[URI][?size=WxH&fps=N&registration=0|1&sync=0|1&pair_ms=N&reopen_ms=N
//                  &stall_ms=N&reset_on_stall=0|1&hotplug=0|1&usb_vendors=1d27:045e:2bc5]
//   openni2:/path/file.oni[?speed=X&repeat=0|1]
// An empty URI is the first device OpenNI2 finds; a URI ending in ".oni" is a recording.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace probeless::openni2 {

struct Openni2Options {
  std::string uri;  // empty: the first device (openni::ANY_DEVICE)
  int width = 640, height = 480;
  int fps = 30;
  bool registration = true;  // IMAGE_REGISTRATION_DEPTH_TO_COLOR where the device has it
  bool sync = true;          // setDepthColorSyncEnabled
  // A colour and a depth frame whose device timestamps differ by at most this much are one
  // RGB-D frame. Default: half a frame period at 30 fps.
  int pair_ms = 16;
  int reopen_ms = 500;  // how often a lost device is looked for again
  int stall_ms = 1000;  // open but silent this long: "stalled"
  // A stalled USB sensor is reset (libusb_reset_device) before it is reopened.
  bool reset_on_stall = true;
  // Reopen at once when a sensor with a configured vendor ID reappears (libusb hotplug).
  bool hotplug = true;
  // The vendor IDs the hotplug watcher listens for (drivers/usb/usb_hotplug.hpp defaults).
  std::vector<std::uint16_t> usb_vendors;
  // Recordings only: 1.0 as recorded, 0 as fast as frames are read (PlaybackControl::setSpeed).
  double speed = 1.0;
  bool repeat = false;  // at the end of a recording: start over (true) or state "ended"

  bool is_file() const { return uri.ends_with(".oni"); }
};

// Parses the part after "openni2:". Throws std::invalid_argument naming a bad key or value,
// or a recording-only option given for a device.
Openni2Options parse_openni2_options(std::string_view spec);

}  // namespace probeless::openni2
