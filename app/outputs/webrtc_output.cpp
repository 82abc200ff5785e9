#include "app/outputs/webrtc_output.hpp"

#include <fmt/format.h>
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
#include "app/outputs/h264_encoder.hpp"
#include "app/outputs/webrtc_session.hpp"

namespace probeless {
namespace {

constexpr gst::RequiredElement kRequired[] = {{"webrtcbin", "gstreamer1.0-plugins-bad"},
                                              {"dtlssrtpenc", "gstreamer1.0-plugins-bad"},
                                              {"srtpenc", "gstreamer1.0-plugins-bad"},
                                              {"nicesink", "gstreamer1.0-nice"},
                                              {"nicesrc", "gstreamer1.0-nice"},
                                              {"rtph264pay", "gstreamer1.0-plugins-good"},
                                              {"capssetter", "gstreamer1.0-plugins-good"},
                                              {"appsrc", "gstreamer1.0-plugins-base"}};

// A resource id a client cannot guess: DELETE of another viewer's session needs it.
std::string new_session_id() {
  static std::mutex mutex;
  static std::mt19937_64 rng{std::random_device{}()};
  std::lock_guard lock(mutex);
  return fmt::format("{:016x}{:016x}", rng(), rng());
}

}  // namespace

std::string webrtc_missing_plugins() {
  try {
    gst::ensure_gstreamer();
  } catch (const std::exception& e) {
    return e.what();
  }
  return gst::missing_element(kRequired);
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
  std::shared_ptr<H264Encoder> encoder;

  // Sessions: fed on the encoder's thread, made and ended on the worker.
  mutable std::mutex sessions_mutex;
  std::map<std::string, std::unique_ptr<webrtc::Session>> sessions;
  std::atomic<int> streaming{0};
  H264Encoder::Subscription subscription;  // before `sessions` go: its callback uses them

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

  void request_keyframe() {
    if (encoder->request_keyframe()) ++keyframes;
  }
  void on_access_unit(const H264AccessUnit& unit);
  void run(std::stop_token stop);
  void answer(Offer offer);
  void sweep();
  void wake() {
    std::lock_guard lock(jobs_mutex);
    look = true;
    jobs_cv.notify_all();
  }
};

void WebRtcOutput::Impl::on_access_unit(const H264AccessUnit& unit) {
  std::lock_guard lock(sessions_mutex);
  if (sessions.empty()) return;  // RTSP's frame
  ++encoded;
  for (auto& [id, session] : sessions) session->push(unit.buffer, unit.capture_ns);
}

WebRtcOutput::WebRtcOutput(WebRtcConfig config, const RtspServerConfig& h264)
    : WebRtcOutput(std::move(config), make_encoder(h264)) {}

std::shared_ptr<H264Encoder> WebRtcOutput::make_encoder(const RtspServerConfig& h264) {
  if (const std::string missing = webrtc_missing_plugins(); !missing.empty())
    throw WebRtcError("webrtc: " + missing);
  try {
    return std::make_shared<H264Encoder>(h264);
  } catch (const RtspServerError& e) {
    throw WebRtcError(std::string("webrtc: ") + e.what());
  }
}

WebRtcOutput::WebRtcOutput(WebRtcConfig config, std::shared_ptr<H264Encoder> encoder)
    : impl_(std::make_shared<Impl>()) {
  Impl& m = *impl_;
  m.config = std::move(config);
  if (m.config.max_sessions < 1) throw WebRtcError("webrtc: max_sessions must be >= 1");
  if (m.config.gather_timeout_ms < 10) throw WebRtcError("webrtc: gather_timeout_ms must be >= 10");
  if (const std::string missing = webrtc_missing_plugins(); !missing.empty())
    throw WebRtcError("webrtc: " + missing);
  if (!encoder) throw WebRtcError("webrtc: no H.264 encoder");
  m.encoder = std::move(encoder);
  m.subscription =
      m.encoder->subscribe([&m](const H264AccessUnit& unit) { m.on_access_unit(unit); });
  m.worker = std::jthread([&m](std::stop_token stop) { m.run(stop); });
  spdlog::info("webrtc: WHEP sessions up to {}, H.264 by {}, ICE on {}", m.config.max_sessions,
               m.encoder->name(),
               m.config.ice_addresses.empty()
                   ? std::string("every interface")
                   : fmt::format("{}", fmt::join(m.config.ice_addresses, ", ")));
}

WebRtcOutput::~WebRtcOutput() {
  stop();
}

std::string WebRtcOutput::encoder_name() const {
  return impl_->encoder->name();
}

std::shared_ptr<H264Encoder> WebRtcOutput::encoder() const {
  return impl_->encoder;
}

void WebRtcOutput::push(std::shared_ptr<const ImageRGB8> frame, TimestampNs capture_ns) {
  Impl& m = *impl_;
  ++m.pushed;
  if (!frame || frame->empty()) return;
  if (m.streaming == 0) {  // nobody watching here: the encoder is left to RTSP's clients, if any
    ++m.no_client;
    return;
  }
  switch (m.encoder->push(std::move(frame), capture_ns)) {
    case H264Encoder::Fed::Sent:
      break;
    case H264Encoder::Fed::QueueFull:
      ++m.queue_full;
      break;
    case H264Encoder::Fed::Stopped:
      ++m.no_client;
      break;
  }
}

void WebRtcOutput::add_status(nlohmann::json& status) const {
  status["webrtc"] = to_json(stats());
  status["h264"] = to_json(impl_->encoder->stats());
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
  m.subscription.reset();  // no access unit after this (a shared encoder goes on for RTSP)
  m.worker.request_stop();
  if (m.worker.joinable()) m.worker.join();
  spdlog::info("webrtc: stopped ({} sessions served)", m.total.load());
}

WebRtcStats WebRtcOutput::stats() const {
  const Impl& m = *impl_;
  WebRtcStats s;
  s.encoder = m.encoder->name();
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
