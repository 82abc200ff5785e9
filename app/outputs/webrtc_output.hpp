#pragma once
// The composite as H.264 over WebRTC to browsers, negotiated through WHEP on the HTTP server
// (app/outputs/whep_endpoint.hpp): about a tenth of MJPEG's bandwidth, played by a plain
// RTCPeerConnection in the viewer page. docs/outputs.md "WebRTC (WHEP)".
//
// One encoder for every session, the service's H.264 encoder (app/outputs/h264_encoder.hpp),
// shared with the RTSP output when both are on, kept to constrained baseline so that every
// browser decodes it:
//
//   appsrc (RGB) ! videoconvert ! I420 ! encoder ! appsink    (access units, H264Encoder)
//
// and one small pipeline per session, fed the same access units:
//
//   appsrc (H.264) ! rtph264pay (the offer's payload type) ! webrtcbin (ICE, DTLS-SRTP)
//
// Frames go to the encoder only while a session streams; a new session asks it for a
// keyframe, and so does a client's PLI. ICE uses host candidates on `ice_addresses` only
// (loopback by default), no STUN or TURN; the answer waits for ICE gathering to complete, so
// it carries every candidate (WHEP without trickle). Offers are handled one at a time on this
// output's own thread, which also ends sessions whose peer failed or left.
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/outputs/output.hpp"
#include "app/outputs/rtsp_server.hpp"
#include "app/outputs/whep_endpoint.hpp"
#include "core/image.hpp"
#include "core/time.hpp"

namespace probeless {

// [webrtc] of the service config (docs/configuration.md).
struct WebRtcConfig {
  // The service's: off by default, like RTSP (it needs gstreamer1.0-plugins-bad and
  // gstreamer1.0-nice). The output itself ignores it.
  bool enabled = false;
  // The local addresses ICE offers as host candidates. Loopback by default: a browser on the
  // box itself (or through an SSH tunnel of the HTTP port... which WebRTC's UDP does not
  // follow: see docs/outputs.md). Empty: every interface's addresses.
  std::vector<std::string> ice_addresses = {"127.0.0.1"};
  // Sessions at once; the next offer gets 503. Each costs a payloader and an SRTP sender,
  // not an encoder: an SBC's uplink (2 Mbit/s each) is the limit first.
  int max_sessions = 8;
  // An answer waits this long at most for ICE gathering (host candidates: milliseconds).
  int gather_timeout_ms = 3000;
  // A session whose client has sent no RTCP, or whose ICE has been "disconnected", this long
  // is ended (a browser tab closed without DELETE, a lost network). Above RTCP's interval:
  // browsers report every second, GStreamer's clients every 5 s (+-50 %) by default.
  int disconnected_timeout_s = 10;
};

struct WebRtcStats {
  std::string encoder;
  int sessions = 0;                      // streaming or being answered now
  std::uint64_t sessions_total = 0;      // answered since start
  std::uint64_t offers_refused = 0;      // bad offers, the session cap, failures
  std::uint64_t frames_pushed = 0;       // offered to push()
  std::uint64_t frames_encoded = 0;      // access units of the encoder while sessions stream
  std::uint64_t dropped_no_client = 0;   // nobody streaming: not encoded for WebRTC
  std::uint64_t dropped_queue_full = 0;  // the encoder was behind
  std::uint64_t keyframe_requests = 0;   // new sessions and clients' PLIs
};

nlohmann::json to_json(const WebRtcStats& stats);

struct WebRtcError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class H264Encoder;

class WebRtcOutput final : public Output, public WhepEndpoint {
 public:
  // Checks the plugins (webrtcbin, nice, the encoder), starts an encoder of its own with the
  // [rtsp] settings `h264` and the worker thread; throws WebRtcError naming the package to
  // install.
  WebRtcOutput(WebRtcConfig config, const RtspServerConfig& h264);
  // The same with the service's encoder, shared with RTSP (output_factory.hpp).
  WebRtcOutput(WebRtcConfig config, std::shared_ptr<H264Encoder> encoder);
  // An encoder for WebRTC from the [rtsp] settings, after checking WebRTC's own plugins (so
  // that a missing webrtcbin is named before an encoder is started for nothing); WebRtcError
  // naming the package to install or the setting.
  static std::shared_ptr<H264Encoder> make_encoder(const RtspServerConfig& h264);
  ~WebRtcOutput() override;
  WebRtcOutput(const WebRtcOutput&) = delete;
  WebRtcOutput& operator=(const WebRtcOutput&) = delete;
  WebRtcOutput(WebRtcOutput&&) = delete;
  WebRtcOutput& operator=(WebRtcOutput&&) = delete;

  std::string encoder_name() const;
  std::shared_ptr<H264Encoder> encoder() const;

  // Any thread; never blocks. `capture_ns` (CLOCK_MONOTONIC) becomes the frame's timestamp.
  void push(std::shared_ptr<const ImageRGB8> frame, TimestampNs capture_ns);

  // WhepEndpoint.
  void offer(std::string sdp, Done done) override;
  bool close_session(std::string_view id) override;

  // Output.
  std::string_view name() const override { return "webrtc"; }
  OutputNeeds needs() const override { return {.colour = true}; }
  // The frame's own time even for a repeat, as RtspServer::offer() (the shared encoder takes
  // one (frame, time) once).
  void offer(const OutputFrame& frame) override { push(frame.colour, frame.timestamp_ns); }
  // "webrtc", and "h264": the encoder's (the same object as RTSP's when both are on).
  void add_status(nlohmann::json& status) const override;
  // Ends every session, stops the encoder and joins the worker. Idempotent.
  void stop() override;

  WebRtcStats stats() const;

  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

// Whether this GStreamer has what WebRtcOutput needs; empty if so, else what is missing and
// its package (the tests skip with it).
std::string webrtc_missing_plugins();

}  // namespace probeless
