#pragma once
// An RTSP player for the latency bench, in the bench's process: GStreamer's rtspsrc (RTP
// interleaved over TCP on loopback, no jitter buffer), rtph264depay, avdec_h264 (FFmpeg's
// decoder, slice threads), videoconvert to RGB, appsink. The settings are those a low-latency
// player uses (`ffplay -fflags nobuffer -flags low_delay`), so what is measured is the
// service's latency and the network's, not a player's buffering.
#include <string>

#include "app/outputs/gst_objects.hpp"
#include "lab/bench/frame_receiver.hpp"

namespace probeless::lab {

class RtspReceiver final : public FrameReceiver {
 public:
  // Starts playing `url`; throws std::runtime_error when the pipeline cannot be built.
  explicit RtspReceiver(const std::string& url);
  ~RtspReceiver() override;
  RtspReceiver(const RtspReceiver&) = delete;
  RtspReceiver& operator=(const RtspReceiver&) = delete;

  // Throws when the pipeline posted an error or the end of the stream.
  std::optional<ReceivedFrame> next(std::chrono::milliseconds timeout) override;

 private:
  void throw_if_ended();

  gst::Element pipeline_;
  gst::Element sink_;
};

}  // namespace probeless::lab
