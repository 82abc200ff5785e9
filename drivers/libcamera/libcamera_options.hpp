#pragma once
// What a `libcamera:` source spec says (docs/drivers.md "libcamera fisheye"):
//   libcamera:[CAMERA_ID][?size=WxH&format=NAME&buffers=N&reopen_ms=N&stall_ms=N]
// CAMERA_ID is libcamera's Camera::id() ("platform/vimc.0 Sensor B", cam -l lists them);
// empty means the first camera libcamera finds. No libcamera headers here: parsing is
// unit-tested on any machine.
#include <string>
#include <string_view>

namespace probeless::libcam {

struct LibcameraOptions {
  std::string camera_id;  // empty: the first camera
  int width = 640, height = 480;
  // libcamera's pixel format name ("SRGGB12", "BGR888", "YUYV", ...); empty: the best one
  // the camera offers at the size (raw Bayer first, as for V4L2).
  std::string format;
  int buffers = 4;      // requests (and frame buffers) in flight
  int reopen_ms = 250;  // how often a lost camera is looked for again
  int stall_ms = 1000;  // open, but no completed request this long: "stalled"
};

// Parses the part after "libcamera:". Throws std::invalid_argument naming a bad key or value.
LibcameraOptions parse_libcamera_options(std::string_view spec);

}  // namespace probeless::libcam
