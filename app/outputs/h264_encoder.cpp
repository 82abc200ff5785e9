#include "app/outputs/h264_encoder.hpp"

#include <fmt/format.h>
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/video/video.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <utility>

#include "app/outputs/gst_objects.hpp"

namespace probeless {
namespace {

// Keyframes asked for more often than this are one keyframe: a burst of PLIs from several
// sessions (or one client's retries) must not turn the stream into all-intra.
constexpr TimestampNs kKeyframeSpacingNs = 250'000'000;

constexpr gst::RequiredElement kRequired[] = {{"appsrc", "gstreamer1.0-plugins-base"},
                                              {"videoconvert", "gstreamer1.0-plugins-base"},
                                              {"appsink", "gstreamer1.0-plugins-base"}};

}  // namespace

std::string choose_h264_encoder(const std::string& wanted) {
  gst::ensure_gstreamer();
  const bool v4l2 = gst::has_element("v4l2h264enc"), x264 = gst::has_element("x264enc");
  if (wanted == "auto") {
    if (v4l2) return "v4l2h264enc";
    if (x264) return "x264enc";
    throw RtspServerError(
        "rtsp: no H.264 encoder: GStreamer has neither v4l2h264enc (a V4L2 memory-to-memory "
        "encoder of the board, gstreamer1.0-plugins-good) nor x264enc (install "
        "gstreamer1.0-plugins-ugly)");
  }
  if (wanted == "x264enc") {
    if (!x264) throw RtspServerError("rtsp: x264enc not found: install gstreamer1.0-plugins-ugly");
    return wanted;
  }
  if (wanted == "v4l2h264enc") {
    if (!v4l2)
      throw RtspServerError(
          "rtsp: v4l2h264enc not found: GStreamer's video4linux2 plugin "
          "(gstreamer1.0-plugins-good) found no V4L2 H.264 encoder device on this machine");
    return wanted;
  }
  throw RtspServerError("rtsp: encoder '" + wanted + "' is not one of auto, v4l2h264enc, x264enc");
}

std::string h264_encoder_launch(const std::string& encoder, const RtspServerConfig& c) {
  if (encoder == "v4l2h264enc")  // the V4L2 controls' own names (v4l2-ctl --list-ctrls)
    return fmt::format(
        "v4l2h264enc extra-controls=\"controls,video_bitrate={},"
        "h264_i_frame_period={}\"",
        c.bitrate_kbps * 1000, c.keyframe_interval);
  // ultrafast: no B-frames, no CABAC (baseline-decodable); zerolatency: no lookahead, so a
  // frame leaves the encoder as soon as it is encoded.
  return fmt::format("x264enc tune=zerolatency speed-preset=ultrafast bitrate={} key-int-max={}",
                     c.bitrate_kbps, c.keyframe_interval);
}

// The subscribers, apart from the encoder so that a Subscription may outlive it. `mutex` is
// held while they are called: unsubscribing waits for a call under way to return.
struct H264Encoder::Subscription::State {
  std::mutex mutex;
  std::map<std::uint64_t, Subscriber> subscribers;
  std::uint64_t next_id = 1;
};

H264Encoder::Subscription::Subscription(Subscription&& other) noexcept
    : state_(std::move(other.state_)), id_(std::exchange(other.id_, 0)) {}

H264Encoder::Subscription& H264Encoder::Subscription::operator=(Subscription&& other) noexcept {
  if (this != &other) {
    reset();
    state_ = std::move(other.state_);
    id_ = std::exchange(other.id_, 0);
  }
  return *this;
}

void H264Encoder::Subscription::reset() {
  if (auto state = std::exchange(state_, nullptr)) {
    std::lock_guard lock(state->mutex);
    state->subscribers.erase(id_);
  }
}

nlohmann::json to_json(const H264EncoderStats& s) {
  return {{"encoder", s.encoder},
          {"subscribers", s.subscribers},
          {"frames_in", s.frames_in},
          {"frames_shared", s.frames_shared},
          {"access_units", s.access_units},
          {"dropped_queue_full", s.dropped_queue_full},
          {"keyframes_forced", s.keyframes_forced}};
}

struct H264Encoder::Impl {
  RtspServerConfig config;
  std::string encoder;
  gst::Element pipeline, appsrc, appsink;

  // What push() keeps between frames: the appsrc's caps and last PTS, and the last frame
  // with its capture time and fate, so that a second output pushing it is answered alike.
  std::mutex feed_mutex;
  int width = 0, height = 0;  // the caps last set on the appsrc
  GstClockTime last_pts = GST_CLOCK_TIME_NONE;
  std::weak_ptr<const ImageRGB8> last_frame;  // weak: its control block cannot be reused
  TimestampNs last_capture_ns = 0;
  Fed last_fed = Fed::Stopped;

  std::shared_ptr<Subscription::State> subscribers = std::make_shared<Subscription::State>();
  // A request within kKeyframeSpacingNs of the last keyframe forced waits, pending, for the
  // first frame after it: deferred, not dropped, or a client joining just after another
  // would wait for the periodic keyframe.
  std::mutex keyframe_mutex;
  TimestampNs last_forced_ns = 0;
  bool keyframe_pending = false;
  std::atomic<std::uint64_t> frames_in{0}, shared{0}, access_units{0}, queue_full{0}, keyframes{0};

  void start();
  Fed push_rgb(std::shared_ptr<const ImageRGB8> frame, TimestampNs capture_ns);
  void on_access_unit(GstSample* sample);
  void force_keyframe();
  void send_pending_keyframe();
};

void H264Encoder::Impl::start() {
  // I420: left to itself videoconvert would offer the encoder 4:4:4, which x264 encodes in a
  // profile few players (and no hardware decoder) accept. Constrained baseline: the profile
  // every browser's WebRTC decodes (Chromium offers it first); x264 at ultrafast is within it.
  const std::string launch = fmt::format(
      "appsrc name=src is-live=true format=time do-timestamp=false block=false "
      "! videoconvert ! video/x-raw,format=I420 ! {} "
      "! video/x-h264,profile=constrained-baseline,stream-format=byte-stream,alignment=au "
      "! appsink name=sink sync=false max-buffers=8 drop=true",
      h264_encoder_launch(encoder, config));
  GError* raw = nullptr;
  pipeline = gst::Element::adopt_sink(gst_parse_launch(launch.c_str(), &raw));
  std::unique_ptr<GError, gst::ErrorDeleter> error(raw);
  if (!pipeline || error)
    throw RtspServerError(fmt::format("h264: cannot build the encoder: {}",
                                      error ? error->message : "no reason given"));
  appsrc = gst::Element::adopt(gst_bin_get_by_name(GST_BIN(pipeline.get()), "src"));
  appsink = gst::Element::adopt(gst_bin_get_by_name(GST_BIN(pipeline.get()), "sink"));
  // The system clock is CLOCK_MONOTONIC, the frames' clock: capture time minus the base time
  // is a frame's running time, and back.
  auto clock = gst::Ref<GstClock, gst_object_unref>::adopt(gst_system_clock_obtain());
  gst_pipeline_use_clock(GST_PIPELINE(pipeline.get()), clock.get());
  GstAppSinkCallbacks callbacks{};
  callbacks.new_sample = [](GstAppSink* sink, gpointer self) {
    auto sample = gst::Sample::adopt(gst_app_sink_pull_sample(sink));
    if (sample) static_cast<Impl*>(self)->on_access_unit(sample.get());
    return GST_FLOW_OK;
  };
  gst_app_sink_set_callbacks(GST_APP_SINK(appsink.get()), &callbacks, this, nullptr);
  if (gst_element_set_state(pipeline.get(), GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw RtspServerError("h264: the encoder pipeline does not start");
}

// Into the appsrc: caps (RGB at the nominal framerate) and a queue bound of max_queued_frames
// frames when the size changes; nothing when that many frames wait already; the PTS the
// capture time on the pipeline's clock, and a repeated frame (NO SIGNAL: an old capture time,
// or one before the pipeline started) shown now. Stopped: the appsrc is flushing.
H264Encoder::Fed H264Encoder::Impl::push_rgb(std::shared_ptr<const ImageRGB8> frame,
                                             TimestampNs capture_ns) {
  auto* src = GST_APP_SRC(appsrc.get());
  const std::size_t frame_bytes = frame->size_bytes();
  const auto queue_bytes = frame_bytes * static_cast<std::size_t>(config.max_queued_frames);
  if (frame->width() != width || frame->height() != height) {
    width = frame->width();
    height = frame->height();
    // A nominal constant rate, not 0/1 ("variable"): x264 given variable-rate input holds each
    // frame until the next one arrives (measured: push-to-decoded p50 41 ms at 30 Hz, against
    // 3 ms with a declared rate). The PTS still say when each frame was taken.
    auto caps = gst::Caps::adopt(gst_caps_new_simple(
        "video/x-raw", "format", G_TYPE_STRING, "RGB", "width", G_TYPE_INT, width, "height",
        G_TYPE_INT, height, "framerate", GST_TYPE_FRACTION, config.framerate, 1, nullptr));
    gst_app_src_set_caps(src, caps.get());
    gst_app_src_set_max_bytes(src, queue_bytes);
  }
  if (gst_app_src_get_current_level_bytes(src) >= queue_bytes) return Fed::QueueFull;
  const GstClockTime base_time = gst_element_get_base_time(pipeline.get());
  const auto capture = static_cast<GstClockTime>(capture_ns);
  GstClockTime pts = capture > base_time ? capture - base_time : GST_CLOCK_TIME_NONE;
  if (pts == GST_CLOCK_TIME_NONE || (last_pts != GST_CLOCK_TIME_NONE && pts <= last_pts)) {
    const GstClockTime now = static_cast<GstClockTime>(monotonic_now_ns()) - base_time;
    pts = last_pts != GST_CLOCK_TIME_NONE ? std::max(last_pts + 1, now) : now;
  }
  last_pts = pts;
  GstBuffer* buffer = gst::wrap_rgb_frame(std::move(frame));
  GST_BUFFER_PTS(buffer) = pts;
  return gst_app_src_push_buffer(src, buffer) == GST_FLOW_OK ? Fed::Sent : Fed::Stopped;
}

void H264Encoder::Impl::on_access_unit(GstSample* sample) {
  GstBuffer* buffer = gst_sample_get_buffer(sample);
  if (!buffer) return;
  ++access_units;
  // Through the segment: a video encoder moves its output 1000 hours later (so that DTS
  // before PTS is never negative) and says so in the segment.
  const GstSegment* segment = gst_sample_get_segment(sample);
  const GstClockTime running =
      segment ? gst_segment_to_running_time(segment, GST_FORMAT_TIME, GST_BUFFER_PTS(buffer))
              : GST_CLOCK_TIME_NONE;
  const H264AccessUnit unit{
      .buffer = buffer,
      .capture_ns =
          GST_CLOCK_TIME_IS_VALID(running)
              ? static_cast<TimestampNs>(running + gst_element_get_base_time(pipeline.get()))
              : monotonic_now_ns(),
      .keyframe = !GST_BUFFER_FLAG_IS_SET(buffer, GST_BUFFER_FLAG_DELTA_UNIT)};
  std::lock_guard lock(subscribers->mutex);
  for (const auto& [id, subscriber] : subscribers->subscribers) subscriber(unit);
}

H264Encoder::H264Encoder(const RtspServerConfig& config) : impl_(std::make_shared<Impl>()) {
  Impl& m = *impl_;
  m.config = config;
  const RtspServerConfig& c = m.config;
  if (c.bitrate_kbps < 64 || c.bitrate_kbps > 100000)
    throw RtspServerError("rtsp: bitrate_kbps must be in 64..100000");
  if (c.keyframe_interval < 1 || c.keyframe_interval > 600)
    throw RtspServerError("rtsp: keyframe_interval must be in 1..600 frames");
  if (c.framerate < 1 || c.framerate > 240)
    throw RtspServerError("rtsp: framerate must be in 1..240");
  if (c.max_queued_frames < 1) throw RtspServerError("rtsp: max_queued_frames must be >= 1");
  m.encoder = choose_h264_encoder(c.encoder);
  if (const std::string missing = gst::missing_element(kRequired); !missing.empty())
    throw RtspServerError("h264: " + missing);
  m.start();
  spdlog::info("h264: {} started ({} kbit/s, keyframe every {} frames)", m.encoder, c.bitrate_kbps,
               c.keyframe_interval);
}

H264Encoder::~H264Encoder() {
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.feed_mutex);
    m.appsrc.reset();
  }
  // NULL joins the streaming threads: no access unit is delivered after this.
  if (m.pipeline) gst_element_set_state(m.pipeline.get(), GST_STATE_NULL);
}

const std::string& H264Encoder::name() const {
  return impl_->encoder;
}

void H264Encoder::Impl::force_keyframe() {
  ++keyframes;
  gst_element_send_event(appsink.get(),
                         gst_video_event_new_upstream_force_key_unit(GST_CLOCK_TIME_NONE, TRUE, 0));
}

void H264Encoder::Impl::send_pending_keyframe() {
  {
    std::lock_guard lock(keyframe_mutex);
    const TimestampNs now = monotonic_now_ns();
    if (!keyframe_pending || now - last_forced_ns < kKeyframeSpacingNs) return;
    keyframe_pending = false;
    last_forced_ns = now;
  }
  force_keyframe();
}

H264Encoder::Fed H264Encoder::push(std::shared_ptr<const ImageRGB8> frame, TimestampNs capture_ns) {
  Impl& m = *impl_;
  if (!frame || frame->empty()) return Fed::Stopped;  // nothing to encode
  std::lock_guard lock(m.feed_mutex);
  if (!m.appsrc) return Fed::Stopped;
  const bool same_frame = !m.last_frame.owner_before(frame) && !frame.owner_before(m.last_frame);
  if (same_frame && capture_ns == m.last_capture_ns) {
    ++m.shared;
    return m.last_fed;
  }
  m.last_frame = frame;
  m.last_capture_ns = capture_ns;
  m.send_pending_keyframe();  // before the frame: it is the one to become a keyframe
  m.last_fed = m.push_rgb(std::move(frame), capture_ns);
  if (m.last_fed == Fed::Sent) ++m.frames_in;
  if (m.last_fed == Fed::QueueFull) ++m.queue_full;
  return m.last_fed;
}

H264Encoder::Subscription H264Encoder::subscribe(Subscriber subscriber) {
  Impl& m = *impl_;
  std::lock_guard lock(m.subscribers->mutex);
  const std::uint64_t id = m.subscribers->next_id++;
  m.subscribers->subscribers.emplace(id, std::move(subscriber));
  return Subscription(m.subscribers, id);
}

bool H264Encoder::request_keyframe() {
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.keyframe_mutex);
    if (m.keyframe_pending) return false;
    m.keyframe_pending = true;
  }
  m.send_pending_keyframe();  // now, unless one was forced within kKeyframeSpacingNs
  return true;
}

H264EncoderStats H264Encoder::stats() const {
  const Impl& m = *impl_;
  H264EncoderStats s;
  s.encoder = m.encoder;
  {
    std::lock_guard lock(m.subscribers->mutex);
    s.subscribers = static_cast<int>(m.subscribers->subscribers.size());
  }
  s.frames_in = m.frames_in;
  s.frames_shared = m.shared;
  s.access_units = m.access_units;
  s.dropped_queue_full = m.queue_full;
  s.keyframes_forced = m.keyframes;
  return s;
}

}  // namespace probeless
