#pragma once
// A WHEP player for the latency bench, in the bench's process: GStreamer's webrtcbin as the
// client (what a browser does, without the browser): a recvonly H.264 offer with its ICE
// candidates on loopback, POSTed to the service's /whep; the answer's stream depayloaded and
// decoded by avdec_h264 (slice threads), converted to RGB into an appsink. As for RTSP, the
// jitter buffer is off (webrtcbin latency=0), so what is measured is the service and the
// network, not a player's buffering. DELETEs its session when destroyed.
#include <mutex>
#include <string>

#include "app/outputs/gst_objects.hpp"
#include "lab/bench/frame_receiver.hpp"

namespace probeless::lab {

class WhepReceiver final : public FrameReceiver {
 public:
  // Negotiates with http://127.0.0.1:`http_port``path`; throws std::runtime_error with the
  // server's answer or GStreamer's reason when it cannot.
  explicit WhepReceiver(int http_port, const std::string& path = "/whep");
  ~WhepReceiver() override;
  WhepReceiver(const WhepReceiver&) = delete;
  WhepReceiver& operator=(const WhepReceiver&) = delete;

  std::optional<ReceivedFrame> next(std::chrono::milliseconds timeout) override;

  // Stops playing without the DELETE, as a browser tab that is closed or loses its network
  // does: the service has to notice by itself (the WebRTC output's tests).
  void vanish();

  // webrtcbin's new stream pad (public for the C callback).
  void on_pad_added(GstPad* pad);

 private:
  void throw_if_ended();

  int port_;
  std::string location_;  // the session's resource, for the DELETE
  gst::Element pipeline_, webrtc_;
  std::mutex sink_mutex_;
  gst::Element sink_;  // made when the stream's pad appears
};

}  // namespace probeless::lab
