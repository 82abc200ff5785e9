#pragma once
// What a `v4l2:` source spec says (docs/drivers.md "Spec"):
//   v4l2:DEVICE[?size=WxH&fps=N&format=FOURCC&buffers=N&latency=N&unity_gain=N&reopen_ms=N]
// DEVICE is a node path (/dev/video0) or, without a leading '/', a card name as
// VIDIOC_QUERYCAP reports it (matched as a prefix, so "vivid" finds "vivid" on any node).
#include <cstdint>
#include <string>
#include <string_view>

namespace probeless::v4l2 {

struct V4l2Options {
  std::string device = "/dev/video0";  // path, or card name when it does not start with '/'
  int width = 640, height = 480;
  double fps = 30;
  std::string format;  // fourcc to insist on ("YUYV", "RG12", ...); empty: the best offered
  int buffers = 4;     // mmap'd driver buffers
  // Frames between setting the controls and the first frame taken with them: the sensor
  // latches registers at frame start, so a frame already exposing when the controls change
  // still has the old ones. 1 fits most sensors; vivid needs 0 (it has no sensor).
  int latency_frames = 1;
  // The raw V4L2_CID_GAIN value that is unity (0 dB); gain units are driver-specific.
  // 0: the control's default value.
  std::int64_t unity_gain = 0;
  int reopen_ms = 250;  // how often a lost device is looked for again
};

// Parses the part after "v4l2:". Throws std::invalid_argument naming a bad key or value.
V4l2Options parse_v4l2_options(std::string_view spec);

}  // namespace probeless::v4l2
