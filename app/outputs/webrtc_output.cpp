#include "app/outputs/webrtc_output.hpp"

#include <fmt/format.h>
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/video/video.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <random>
#include <stop_token>
#include <thread>

#include "app/outputs/gst_objects.hpp"
#include "app/outputs/webrtc_session.hpp"

namespace probeless {
namespace {

struct RequiredElement {
  const char* name;
  const char* package;
};
constexpr RequiredElement kRequired[] = {{"webrtcbin", "gstreamer1.0-plugins-bad"},
                                         {"dtlssrtpenc", "gstreamer1.0-plugins-bad"},
                                         {"srtpenc", "gstreamer1.0-plugins-bad"},
                                         {"nicesink", "gstreamer1.0-nice"},
                                         {"nicesrc", "gstreamer1.0-nice"},
                                         {"rtph264pay", "gstreamer1.0-plugins-good"},
                                         {"capssetter", "gstreamer1.0-plugins-good"},
                                         {"appsrc", "gstreamer1.0-plugins-base"},
                                         {"videoconvert", "gstreamer1.0-plugins-base"}};

bool has_element(const char* name) {
  return static_cast<bool>(gst::ElementFactory::adopt(gst_element_factory_find(name)));
}

// A resource id a client cannot guess: DELETE of another viewer's session needs it.
std::string new_session_id() {
  static std::mutex mutex;
  static std::mt19937_64 rng{std::random_device{}()};
  std::lock_guard lock(mutex);
  return fmt::format("{:016x}{:016x}", rng(), rng());
}

// Keyframes asked for more often than this are one keyframe: a burst of PLIs from several
// sessions (or one client's retries) must not turn the stream into all-intra.
constexpr TimestampNs kKeyframeSpacingNs = 250'000'000;

}  // namespace

std::string webrtc_missing_plugins() {
  try {
    gst::ensure_gstreamer();
  } catch (const std::exception& e) {
    return e.what();
  }
  for (const auto& e : kRequired)
    if (!has_element(e.name))
      return fmt::format("GStreamer element {} (install {})", e.name, e.package);
  return {};
}

nlohmann::json to_json(const WebRtcStats& s) {
  return {{"encoder", s.encoder},
          {"sessions", s.sessions},
          {"sessions_total", s.sessions_total},
          {"offers_refused", s.offers_refused},
          {"frames_pushed", s.frames_pushed},
          {"frames_encoded", s.frames_encoded},
          {"dropped_no_client", s.dropped_no_client},
          {"dropped_queue_full", s.dropped_queue_full},
          {"keyframe_requests", s.keyframe_requests}};
}

struct WebRtcOutput::Impl {
  WebRtcConfig config;
  RtspServerConfig h264;
  std::string encoder;

  // The shared encoder; `feed_mutex` guards what push() keeps between frames.
  gst::Element pipeline, appsrc, appsink;
  std::mutex feed_mutex;
  gst::RgbFeed rgb;
  std::atomic<TimestampNs> last_keyframe_request{0};

  // Sessions: fed on the encoder's thread, made and ended on the worker.
  mutable std::mutex sessions_mutex;
  std::map<std::string, std::unique_ptr<webrtc::Session>> sessions;
  std::atomic<int> streaming{0};

  // The worker's queue: offers, DELETEs, and wake-ups to look at the sessions' states.
  struct Offer {
    std::string sdp;
    Done done;
  };
  std::mutex jobs_mutex;
  std::condition_variable_any jobs_cv;
  std::deque<Offer> offers;
  std::vector<std::string> closing;
  bool look = false;
  bool stopped = false;
  std::jthread worker;

  std::atomic<std::uint64_t> pushed{0}, encoded{0}, no_client{0}, queue_full{0}, keyframes{0},
      total{0}, refused{0};

  void start_encoder();
  void request_keyframe();
  void on_access_unit(GstSample* sample);
  void run(std::stop_token stop);
  void answer(Offer offer);
  void sweep();
  void wake() {
    std::lock_guard lock(jobs_mutex);
    look = true;
    jobs_cv.notify_all();
  }
};

void WebRtcOutput::Impl::start_encoder() {
  // Constrained baseline: the profile every browser's WebRTC decodes (Chromium offers it
  // first); x264 at ultrafast is already within it.
  const std::string launch = fmt::format(
      "appsrc name=src is-live=true format=time do-timestamp=false block=false "
      "! videoconvert ! video/x-raw,format=I420 ! {} "
      "! video/x-h264,profile=constrained-baseline,stream-format=byte-stream,alignment=au "
      "! appsink name=sink sync=false max-buffers=8 drop=true",
      h264_encoder_launch(encoder, h264));
  GError* raw = nullptr;
  pipeline = gst::Element::adopt_sink(gst_parse_launch(launch.c_str(), &raw));
  std::unique_ptr<GError, gst::ErrorDeleter> error(raw);
  if (!pipeline || error)
    throw WebRtcError(fmt::format("webrtc: cannot build the encoder: {}",
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
    throw WebRtcError("webrtc: the encoder pipeline does not start");
}

void WebRtcOutput::Impl::request_keyframe() {
  const TimestampNs now = monotonic_now_ns();
  TimestampNs last = last_keyframe_request;
  if (now - last < kKeyframeSpacingNs || !last_keyframe_request.compare_exchange_strong(last, now))
    return;
  ++keyframes;
  gst_element_send_event(appsink.get(),
                         gst_video_event_new_upstream_force_key_unit(GST_CLOCK_TIME_NONE, TRUE, 0));
}

void WebRtcOutput::Impl::on_access_unit(GstSample* sample) {
  GstBuffer* buffer = gst_sample_get_buffer(sample);
  if (!buffer) return;
  ++encoded;
  // Through the segment: a video encoder moves its output 1000 hours later (so that DTS
  // before PTS is never negative) and says so in the segment.
  const GstSegment* segment = gst_sample_get_segment(sample);
  const GstClockTime running =
      segment ? gst_segment_to_running_time(segment, GST_FORMAT_TIME, GST_BUFFER_PTS(buffer))
              : GST_CLOCK_TIME_NONE;
  const TimestampNs capture =
      GST_CLOCK_TIME_IS_VALID(running)
          ? static_cast<TimestampNs>(running + gst_element_get_base_time(pipeline.get()))
          : monotonic_now_ns();
  std::lock_guard lock(sessions_mutex);
  for (auto& [id, session] : sessions) session->push(buffer, capture);
}

WebRtcOutput::WebRtcOutput(WebRtcConfig config, const RtspServerConfig& h264)
    : impl_(std::make_shared<Impl>()) {
  Impl& m = *impl_;
  m.config = std::move(config);
  m.h264 = h264;
  if (m.config.max_sessions < 1) throw WebRtcError("webrtc: max_sessions must be >= 1");
  if (m.config.gather_timeout_ms < 10) throw WebRtcError("webrtc: gather_timeout_ms must be >= 10");
  if (m.config.max_queued_frames < 1) throw WebRtcError("webrtc: max_queued_frames must be >= 1");
  if (const std::string missing = webrtc_missing_plugins(); !missing.empty())
    throw WebRtcError("webrtc: " + missing);
  try {
    m.encoder = choose_h264_encoder(h264.encoder);
  } catch (const RtspServerError& e) {
    throw WebRtcError(std::string("webrtc: ") + e.what());
  }
  m.start_encoder();
  m.worker = std::jthread([&m](std::stop_token stop) { m.run(stop); });
  spdlog::info(
      "webrtc: WHEP sessions up to {}, H.264 by {}, ICE on {}", m.config.max_sessions, m.encoder,
      m.config.ice_addresses.empty() ? std::string("every interface")
                                     : fmt::format("{}", fmt::join(m.config.ice_addresses, ", ")));
}

WebRtcOutput::~WebRtcOutput() {
  stop();
}

std::string WebRtcOutput::encoder_name() const {
  return impl_->encoder;
}

void WebRtcOutput::push(std::shared_ptr<const ImageRGB8> frame, TimestampNs capture_ns) {
  Impl& m = *impl_;
  ++m.pushed;
  if (!frame || frame->empty()) return;
  if (m.streaming == 0) {  // nobody watching: not even converted
    ++m.no_client;
    return;
  }
  std::lock_guard lock(m.feed_mutex);
  if (!m.appsrc) return;
  const gst::FeedResult fed = gst::push_rgb_frame(
      GST_APP_SRC(m.appsrc.get()), m.rgb, std::move(frame), capture_ns,
      gst_element_get_base_time(m.pipeline.get()), m.h264.framerate, m.config.max_queued_frames);
  if (fed == gst::FeedResult::QueueFull) ++m.queue_full;
  if (fed == gst::FeedResult::Refused) ++m.no_client;
}

void WebRtcOutput::offer(std::string sdp, Done done) {
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.jobs_mutex);
    // A flood of offers waits for nothing: beyond the cap, queued ones could not be served.
    if (!m.stopped && m.offers.size() < static_cast<std::size_t>(m.config.max_sessions)) {
      m.offers.push_back({std::move(sdp), std::move(done)});
      m.jobs_cv.notify_all();
      return;
    }
  }
  ++m.refused;
  done(WhepAnswer::refusal(503, "too many WebRTC offers waiting, or the output is stopping"));
}

bool WebRtcOutput::close_session(std::string_view id) {
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.sessions_mutex);
    if (!m.sessions.contains(std::string(id))) return false;
  }
  std::lock_guard lock(m.jobs_mutex);
  m.closing.emplace_back(id);
  m.jobs_cv.notify_all();
  return true;
}

void WebRtcOutput::Impl::run(std::stop_token stop) {
  while (true) {
    std::optional<Offer> offer;
    std::vector<std::string> to_close;
    {
      std::unique_lock lock(jobs_mutex);
      jobs_cv.wait_for(lock, stop, std::chrono::milliseconds(500),
                       [&] { return !offers.empty() || !closing.empty() || look; });
      if (stop.stop_requested()) break;
      if (!offers.empty()) {
        offer = std::move(offers.front());
        offers.pop_front();
      }
      to_close.swap(closing);
      look = false;
    }
    for (const std::string& id : to_close) {
      std::unique_ptr<webrtc::Session> ended;
      {
        std::lock_guard lock(sessions_mutex);
        if (auto it = sessions.find(id); it != sessions.end()) {
          ended = std::move(it->second);
          sessions.erase(it);
          streaming = static_cast<int>(sessions.size());
        }
      }
      if (ended)
        spdlog::info("webrtc: session {} closed by its client ({} frames)", id,
                     ended->frames_sent());
    }
    if (offer) answer(std::move(*offer));
    sweep();
  }
  // Stopping: every offer still waiting is refused, every session ended.
  std::deque<Offer> left;
  {
    std::lock_guard lock(jobs_mutex);
    left.swap(offers);
  }
  for (auto& o : left) o.done(WhepAnswer::refusal(503, "the WebRTC output is stopping"));
  std::map<std::string, std::unique_ptr<webrtc::Session>> ended;
  {
    std::lock_guard lock(sessions_mutex);
    ended.swap(sessions);
    streaming = 0;
  }
  ended.clear();
}

void WebRtcOutput::Impl::answer(Offer offer) {
  WhepAnswer result;
  bool full = false;
  {
    std::lock_guard lock(sessions_mutex);
    full = sessions.size() >= static_cast<std::size_t>(config.max_sessions);
  }
  if (full) {
    ++refused;
    offer.done(WhepAnswer::refusal(
        503,
        fmt::format("{} WebRTC sessions already ([webrtc] max_sessions)", config.max_sessions)));
    return;
  }
  try {
    const WhepOfferChoice format = choose_whep_format(offer.sdp);
    std::string id = new_session_id();
    auto session = std::make_unique<webrtc::Session>(
        id, offer.sdp, format, config,
        webrtc::SessionHooks{.changed = [this] { wake(); },
                             .keyframe_wanted = [this] { request_keyframe(); }});
    result.sdp = session->answer();
    result.session_id = id;
    {
      std::lock_guard lock(sessions_mutex);
      sessions.emplace(id, std::move(session));
      streaming = static_cast<int>(sessions.size());
    }
    ++total;
    request_keyframe();  // the new client starts at once, not at the next periodic keyframe
    spdlog::info("webrtc: session {} answered (H.264 payload type {}, {} now)", id,
                 format.payload_type, streaming.load());
  } catch (const WhepOfferError& e) {
    ++refused;
    result = WhepAnswer::refusal(400, std::string("bad offer: ") + e.what());
  } catch (const WebRtcError& e) {
    ++refused;
    result = WhepAnswer::refusal(500, e.what());
    spdlog::warn("{}", e.what());
  }
  offer.done(std::move(result));
}

void WebRtcOutput::Impl::sweep() {
  const TimestampNs now = monotonic_now_ns();
  const TimestampNs connect_timeout = 15'000'000'000;  // ICE with host candidates: < 1 s
  const TimestampNs disconnected =
      static_cast<TimestampNs>(config.disconnected_timeout_s) * 1'000'000'000;
  std::vector<std::unique_ptr<webrtc::Session>> ended;
  {
    std::lock_guard lock(sessions_mutex);
    for (auto it = sessions.begin(); it != sessions.end();) {
      if (it->second->finished(now, connect_timeout, disconnected)) {
        ended.push_back(std::move(it->second));
        it = sessions.erase(it);
      } else {
        ++it;
      }
    }
    streaming = static_cast<int>(sessions.size());
  }
  for (auto& s : ended) {
    if (const std::string error = s->error(); !error.empty())
      spdlog::warn("webrtc: session {} failed: {}", s->id(), error);
    else
      spdlog::info("webrtc: session {} ended: its peer failed or left ({} frames)", s->id(),
                   s->frames_sent());
  }
}

void WebRtcOutput::stop() {
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.jobs_mutex);
    if (m.stopped) return;
    m.stopped = true;
  }
  m.worker.request_stop();
  if (m.worker.joinable()) m.worker.join();
  {
    std::lock_guard lock(m.feed_mutex);
    m.appsrc.reset();
  }
  if (m.pipeline) gst_element_set_state(m.pipeline.get(), GST_STATE_NULL);
  spdlog::info("webrtc: stopped ({} sessions served)", m.total.load());
}

WebRtcStats WebRtcOutput::stats() const {
  const Impl& m = *impl_;
  WebRtcStats s;
  s.encoder = m.encoder;
  {
    std::lock_guard lock(m.sessions_mutex);
    s.sessions = static_cast<int>(m.sessions.size());
  }
  s.sessions_total = m.total;
  s.offers_refused = m.refused;
  s.frames_pushed = m.pushed;
  s.frames_encoded = m.encoded;
  s.dropped_no_client = m.no_client;
  s.dropped_queue_full = m.queue_full;
  s.keyframe_requests = m.keyframes;
  return s;
}

}  // namespace probeless
