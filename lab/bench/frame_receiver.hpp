#pragma once
// The receiving end of one output path for `probeless bench latency` (docs/outputs.md
// "Glass-to-glass latency"): a client in the bench's own process that takes the service's
// stream over loopback and decodes every frame to RGB, as a viewer would. The bench reads the
// capture stamp (core/capture_stamp.hpp) from the decoded picture; a receiver only says when
// the frame was decoded. One class per path (MJPEG, RTSP; WebRTC when the service has it).
#include <chrono>
#include <optional>

#include "core/image.hpp"
#include "core/time.hpp"

namespace probeless::lab {

struct ReceivedFrame {
  ImageRGB8 image;
  TimestampNs decoded_ns = 0;  // CLOCK_MONOTONIC as the decoded picture was in hand
  // What the transport itself said of the frame's time in the service, when it says
  // anything: MJPEG's X-UStreamer-Latency (capture to the part being sent), in ms.
  std::optional<double> service_ms;
};

class FrameReceiver {
 public:
  virtual ~FrameReceiver() = default;
  // The next decoded frame; nullopt when none came within `timeout`. Throws
  // std::runtime_error when the stream breaks.
  virtual std::optional<ReceivedFrame> next(std::chrono::milliseconds timeout) = 0;
};

}  // namespace probeless::lab
