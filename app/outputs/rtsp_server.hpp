#pragma once
// The composite as H.264 over RTSP (gst-rtsp-server), beside the MJPEG/HTTP output, for
// players that want a real video stream: `ffplay -rtsp_transport tcp rtsp://HOST:8554/probeless`,
// VLC, NVRs and Home Assistant's generic camera.
//
// One shared media, whatever the number of clients, fed the service's one H.264 encoder
// (app/outputs/h264_encoder.hpp, shared with the WebRTC output):
//
//   appsrc (H.264 access units, PTS from the frames' capture clock)
//     ! rtph264pay (SPS/PPS with every keyframe, so a client joining late starts at the next)
//
// The encoder is the board's V4L2 memory-to-memory one (v4l2h264enc) when GStreamer has it,
// else x264enc (ultrafast, zerolatency); encoder_name() says which. A new media and a client's
// PLAY ask it for a keyframe. The GLib main loop runs on this object's own thread. push()
// (offer() as a pipeline Output) never blocks the pipeline: with no client playing, or with the
// encoder `max_queued_frames` behind, the frame is dropped and counted. docs/outputs.md "RTSP"
// has the details and the measured cost.
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "app/outputs/output.hpp"
#include "core/image.hpp"
#include "core/time.hpp"

namespace probeless {

// [rtsp] of the service config (docs/configuration.md).
struct RtspServerConfig {
  // The service's: off by default, it needs GStreamer's encoder plugins, which a minimal
  // install may not have. The server itself ignores it.
  bool enabled = false;
  std::string address = "127.0.0.1";  // as [http]: an appliance opens to the network on purpose
  int port = 8554;                    // the RTSP default; 0 takes an ephemeral port (tests)
  std::string path = "/probeless";    // "/name[/name...]" of letters, digits, '.', '_', '-'
  int bitrate_kbps = 2000;     // ~2 Mbit/s: a 640x480 scene at 30 Hz without visible blocking
  int keyframe_interval = 30;  // frames; a client joining late waits up to this long
  // The rate the stream declares (the camera's). The encoder budgets bitrate_kbps per frame
  // with it; frames keep their own timestamps.
  int framerate = 30;
  // "auto" (v4l2h264enc if present, else x264enc), or one of them by name.
  std::string encoder = "auto";
  // Frames waiting in the appsrc before new ones are dropped: the encoder is behind.
  int max_queued_frames = 2;
  // RTSP basic authentication when both are set (RFC 2326 reuses HTTP's; every player asks
  // for rtsp://user:password@host/...): without them any client on the address may watch.
  std::string user, password;
  // Sessions at once (gst-rtsp-server's session pool); a SETUP beyond gets 503. 0: no cap.
  // Each session of a shared media costs a payloader branch, not an encoder: 16 is an SBC's
  // uplink at 2 Mbit/s long before its CPU.
  int max_sessions = 16;
};

struct RtspServerStats {
  std::string url;
  std::string encoder;
  int clients = 0;                       // RTSP connections open
  std::uint64_t media_created = 0;       // media pipelines built: one per viewing period
  std::uint64_t frames_pushed = 0;       // offered to push()
  std::uint64_t frames_sent = 0;         // handed to the encoder (or handed by WebRTC already)
  std::uint64_t dropped_no_client = 0;   // nobody playing: not encoded for RTSP
  std::uint64_t dropped_queue_full = 0;  // the encoder was behind
  std::uint64_t access_units_sent = 0;   // encoded pictures into the media
  std::uint64_t keyframe_requests = 0;   // new media, clients' PLAYs, restarts after a drop
};

nlohmann::json to_json(const RtspServerStats& stats);

struct RtspServerError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws RtspServerError for a mount path gst-rtsp-server would not serve as written.
void check_rtsp_path(const std::string& path);

class H264Encoder;

class RtspServer final : public Output {
 public:
  // Checks the plugins, binds and starts serving; throws RtspServerError with the reason
  // (port in use, encoder missing, bad path or config). Without `encoder`, one of its own
  // from `config`; the service hands the one it shares with WebRTC (output_factory.hpp).
  explicit RtspServer(RtspServerConfig config, std::shared_ptr<H264Encoder> encoder = nullptr);
  ~RtspServer() override;
  RtspServer(const RtspServer&) = delete;
  RtspServer& operator=(const RtspServer&) = delete;
  RtspServer(RtspServer&&) = delete;
  RtspServer& operator=(RtspServer&&) = delete;

  int port() const;                  // the bound port (the ephemeral one with port 0)
  std::string url() const override;  // "rtsp://127.0.0.1:8554/probeless"
  std::string encoder_name() const;  // "x264enc" or "v4l2h264enc"
  std::shared_ptr<H264Encoder> encoder() const;

  // Any thread; never blocks. The frame is referenced, not copied, until encoded.
  // `capture_ns` is the frame's CLOCK_MONOTONIC capture time: it becomes the PTS.
  void push(std::shared_ptr<const ImageRGB8> frame, TimestampNs capture_ns);

  // Disconnects every client, stops the media and joins the thread. Idempotent.
  void stop() override;

  // Output: the raw composite for the encoder. A NO SIGNAL repeat keeps the last good
  // frame's capture time; the stream shows it now.
  std::string_view name() const override { return "rtsp"; }
  OutputNeeds needs() const override { return {.colour = true}; }
  // The frame's own time even for a repeat: WebRTC offers it too, and the shared encoder
  // takes one (frame, time) once; it shows a time not after the last frame's now.
  void offer(const OutputFrame& frame) override { push(frame.colour, frame.timestamp_ns); }
  // "rtsp", and "h264": the encoder's (the same object as WebRTC's when both are on).
  void add_status(nlohmann::json& status) const override;
  // The main loop beats "rtsp" every 250 ms from a timeout source (issue #20 item 6).
  void watch(HeartbeatRegistry& heartbeats) override;

  RtspServerStats stats() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace probeless
