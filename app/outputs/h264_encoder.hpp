#pragma once
// The service's one H.264 encoder, shared by the RTSP and the WebRTC outputs (issue #22
// item 1): what both stream is encoded once, whatever the number of outputs and clients.
//
//   appsrc (RGB, PTS from the capture clock) ! videoconvert ! I420 ! encoder
//     ! constrained baseline, byte-stream, one access unit a buffer ! appsink
//
// The encoder is the [rtsp] choice (choose_h264_encoder()) with its bitrate, keyframe interval
// and frame rate. Each access unit goes to every subscriber, on the encoder's streaming
// thread, with its capture time on CLOCK_MONOTONIC. The outputs push frames only while one of
// their clients watches, so with nobody watching nothing is converted or encoded; the
// pipeline itself idles in PLAYING. docs/outputs.md "One H.264 encoder".
#include <gst/gst.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "app/outputs/rtsp_server.hpp"
#include "core/image.hpp"
#include "core/time.hpp"

namespace probeless {

// "auto", "v4l2h264enc" or "x264enc" resolved against the installed GStreamer plugins;
// RtspServerError naming the Debian package to install when the wanted one is missing.
std::string choose_h264_encoder(const std::string& wanted);

// The encoder's gst-launch description with the config's bitrate and keyframe interval.
std::string h264_encoder_launch(const std::string& encoder, const RtspServerConfig& config);

// One encoded picture as the subscribers get it. `buffer` is borrowed for the callback: a
// subscriber that keeps it (to push it on) takes a reference or a gst_buffer_copy().
struct H264AccessUnit {
  GstBuffer* buffer = nullptr;  // Annex B byte-stream; SPS/PPS precede every keyframe
  TimestampNs capture_ns = 0;   // the frame's capture time (CLOCK_MONOTONIC)
  bool keyframe = false;
};

struct H264EncoderStats {
  std::string encoder;                   // "x264enc" or "v4l2h264enc"
  int subscribers = 0;                   // outputs taking the access units
  std::uint64_t frames_in = 0;           // distinct frames handed to the encoder
  std::uint64_t frames_shared = 0;       // pushes of a frame another output had handed in
  std::uint64_t access_units = 0;        // out of the encoder
  std::uint64_t dropped_queue_full = 0;  // the encoder was behind
  std::uint64_t keyframes_forced = 0;    // requests that reached the encoder
};

nlohmann::json to_json(const H264EncoderStats& stats);

class H264Encoder {
 public:
  enum class Fed {
    Sent,       // queued for encoding (or was already, pushed by another output)
    QueueFull,  // `max_queued_frames` wait already: dropped
    Stopped,    // the encoder is going down
  };
  using Subscriber = std::function<void(const H264AccessUnit&)>;

  // Until destroyed (or reset()), its subscriber gets every access unit; when the destructor
  // returns the subscriber is not running and never will again, so an output can drop its
  // subscription and then free what the callback uses.
  class Subscription {
   public:
    Subscription() = default;
    ~Subscription() { reset(); }
    Subscription(Subscription&& other) noexcept;
    Subscription& operator=(Subscription&& other) noexcept;
    Subscription(const Subscription&) = delete;
    Subscription& operator=(const Subscription&) = delete;
    void reset();

    struct State;

   private:
    friend class H264Encoder;
    Subscription(std::shared_ptr<State> state, std::uint64_t id) : state_(state), id_(id) {}
    std::shared_ptr<State> state_;
    std::uint64_t id_ = 0;
  };

  // Validates the [rtsp] encoder settings, checks the plugins and starts the pipeline;
  // throws RtspServerError naming the setting or the Debian package.
  explicit H264Encoder(const RtspServerConfig& config);
  ~H264Encoder();
  H264Encoder(const H264Encoder&) = delete;
  H264Encoder& operator=(const H264Encoder&) = delete;

  const std::string& name() const;  // "x264enc" or "v4l2h264enc"

  // Any thread; never blocks. `capture_ns` (CLOCK_MONOTONIC) becomes the PTS; one not after
  // the last frame's (a NO SIGNAL repeat) is shown now. The same frame with the same capture
  // time pushed again, as two outputs offered one composite do, is encoded once.
  Fed push(std::shared_ptr<const ImageRGB8> frame, TimestampNs capture_ns);

  [[nodiscard]] Subscription subscribe(Subscriber subscriber);

  // The next frame becomes a keyframe with SPS/PPS (a new client, a lost packet). At most one
  // keyframe is forced in 250 ms, so that a burst of requests from several clients cannot make
  // the stream all-intra: a request within that time is kept for the first frame after it.
  // False when a request was pending already (this one is answered by the same keyframe).
  bool request_keyframe();

  H264EncoderStats stats() const;

  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

}  // namespace probeless
