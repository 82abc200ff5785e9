#include "app/outputs/webrtc_session.hpp"

#define GST_USE_UNSTABLE_API  // gst/webrtc is marked unstable in 1.22
#include <fmt/format.h>
#include <gst/app/gstappsrc.h>
#include <gst/sdp/sdp.h>
#include <gst/video/video.h>
#include <gst/webrtc/webrtc.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <memory>

namespace probeless::webrtc {
namespace {

using Promise = gst::Ref<GstPromise, gst_promise_unref>;
using Transceiver = gst::Ref<GstWebRTCRTPTransceiver, gst_object_unref>;
using Ice = gst::Ref<GstWebRTCICE, gst_object_unref>;
using Description = gst::Ref<GstWebRTCSessionDescription, gst_webrtc_session_description_free>;

// A client that stops reading (or a slow link) would otherwise queue frames without end;
// past this the session skips to the next keyframe. ~1 s of 2 Mbit/s.
constexpr guint64 kMaxQueuedBytes = 256 * 1024;

// webrtcbin answers through GstPromise. gst_promise_wait() has no timeout, so the reply is
// waited for with a condition variable; the state is shared with the promise's callback,
// which may come after a wait that gave up.
struct PromiseState {
  std::mutex mutex;
  std::condition_variable cv;
  bool done = false;
};

void promise_changed(GstPromise*, gpointer data) {
  auto& state = **static_cast<std::shared_ptr<PromiseState>*>(data);
  std::lock_guard lock(state.mutex);
  state.done = true;
  state.cv.notify_all();
}

void delete_promise_state(gpointer data) {
  delete static_cast<std::shared_ptr<PromiseState>*>(data);
}

// Emits `signal` on webrtcbin with a new promise as its last argument, waits for the reply
// and returns it (owned by the promise, valid while it lives); throws WebRtcError naming
// `what` on a timeout or an error reply.
class Call {
 public:
  Call() : state_(std::make_shared<PromiseState>()) {
    promise_ = Promise::adopt(gst_promise_new_with_change_func(
        promise_changed, new std::shared_ptr<PromiseState>(state_), delete_promise_state));
  }
  GstPromise* promise() const { return promise_.get(); }
  const GstStructure* wait(const char* what) {
    {
      std::unique_lock lock(state_->mutex);
      if (!state_->cv.wait_for(lock, std::chrono::seconds(5), [&] { return state_->done; })) {
        gst_promise_interrupt(promise_.get());
        throw WebRtcError(fmt::format("webrtc: {}: no reply from webrtcbin", what));
      }
    }
    if (gst_promise_wait(promise_.get()) != GST_PROMISE_RESULT_REPLIED)
      throw WebRtcError(fmt::format("webrtc: {}: interrupted", what));
    const GstStructure* reply = gst_promise_get_reply(promise_.get());
    GError* raw = nullptr;
    if (reply && gst_structure_has_field(reply, "error") &&
        gst_structure_get(reply, "error", G_TYPE_ERROR, &raw, nullptr)) {
      std::unique_ptr<GError, gst::ErrorDeleter> error(raw);
      throw WhepOfferError(fmt::format("{}: {}", what, error ? error->message : "refused"));
    }
    return reply;
  }

 private:
  std::shared_ptr<PromiseState> state_;
  Promise promise_;
};

void on_ice_state_cb(GstElement*, GParamSpec*, gpointer self) {
  static_cast<Session*>(self)->on_ice_state();
}
void on_gathering_cb(GstElement*, GParamSpec*, gpointer self) {
  static_cast<Session*>(self)->on_gathering_state();
}
void on_ssrc_active_cb(GstElement*, guint, guint, gpointer self) {
  static_cast<Session*>(self)->on_rtcp();
}
void on_bye_cb(GstElement*, guint, guint, gpointer self) {
  static_cast<Session*>(self)->on_bye();
}

// A client's PLI or FIR reaches the payloader as an upstream force-key-unit event; it stops
// at this session's appsrc, so it is passed on to the shared encoder from here.
GstPadProbeReturn on_upstream_event(GstPad*, GstPadProbeInfo* info, gpointer hooks) {
  GstEvent* event = GST_PAD_PROBE_INFO_EVENT(info);
  if (event && gst_video_event_is_force_key_unit(event))
    static_cast<SessionHooks*>(hooks)->keyframe_wanted();
  return GST_PAD_PROBE_OK;
}

// The stream's RTP caps as the answer states them (the codec preference) and as the
// payloader's output is rewritten to, so that the two never differ.
std::string rtp_caps(const WhepOfferChoice& format) {
  return fmt::format(
      "application/x-rtp,media=(string)video,encoding-name=(string)H264,clock-rate=(int)90000,"
      "payload=(int){},packetization-mode=(string)1,profile-level-id=(string){}",
      format.payload_type, format.profile_level_id);
}

}  // namespace

Session::Session(std::string id, const std::string& offer, const WhepOfferChoice& format,
                 const WebRtcConfig& config, SessionHooks hooks)
    : id_(std::move(id)), hooks_(std::move(hooks)) {
  // capssetter replaces the payloader's caps with the ones negotiated, whole. The payloader
  // adds the stream's SPS/PPS (sprop-parameter-sets) once it has seen them, and its level
  // (x264 picks 3.0 for 640x480, the offer names its own): webrtcbin takes any change of
  // caps after the answer for a need to renegotiate and holds the stream until then (seen:
  // one frame, then nothing). SPS/PPS go in-band before every keyframe (config-interval=-1),
  // and decoders take any level (Chromium offers level-asymmetry-allowed).
  const std::string launch = fmt::format(
      "appsrc name=src is-live=true format=time do-timestamp=false block=false "
      "caps=video/x-h264,stream-format=byte-stream,alignment=au "
      "! rtph264pay pt={0} config-interval=-1 "
      "! capssetter join=false replace=true caps=\"{1}\" "
      "! webrtcbin name=webrtc bundle-policy=max-bundle",
      format.payload_type, rtp_caps(format));
  GError* raw = nullptr;
  pipeline_ = gst::Element::adopt_sink(gst_parse_launch(launch.c_str(), &raw));
  std::unique_ptr<GError, gst::ErrorDeleter> error(raw);
  if (!pipeline_ || error)
    throw WebRtcError(fmt::format("webrtc: cannot build a session: {}",
                                  error ? error->message : "no reason given"));
  src_ = gst::Element::adopt(gst_bin_get_by_name(GST_BIN(pipeline_.get()), "src"));
  webrtc_ = gst::Element::adopt(gst_bin_get_by_name(GST_BIN(pipeline_.get()), "webrtc"));
  {
    auto pad =
        gst::Ref<GstPad, gst_object_unref>::adopt(gst_element_get_static_pad(src_.get(), "src"));
    gst_pad_add_probe(pad.get(), GST_PAD_PROBE_TYPE_EVENT_UPSTREAM, on_upstream_event, &hooks_,
                      nullptr);
  }
  g_signal_connect(webrtc_.get(), "notify::ice-connection-state", G_CALLBACK(on_ice_state_cb),
                   this);
  g_signal_connect(webrtc_.get(), "notify::ice-gathering-state", G_CALLBACK(on_gathering_cb), this);
  // The client's RTCP says it is there: a WebRTC receiver sends reports (and transport-cc
  // feedback) every second or more often, and a BYE when it closes. ICE alone does not say it:
  // libnice, as webrtcbin 1.22 sets it up, keeps a pair "connected" after its peer has gone
  // (measured: a client that vanished was still connected a minute later).
  rtpbin_ = gst::Element::adopt(gst_bin_get_by_name(GST_BIN(webrtc_.get()), "rtpbin"));
  if (rtpbin_) {
    g_signal_connect(rtpbin_.get(), "on-ssrc-active", G_CALLBACK(on_ssrc_active_cb), this);
    g_signal_connect(rtpbin_.get(), "on-bye-ssrc", G_CALLBACK(on_bye_cb), this);
  } else {
    spdlog::warn("webrtc: no rtpbin in webrtcbin: a vanished client is found by ICE only");
  }
  try {
    negotiate(offer, format, config);
  } catch (...) {
    gst_element_set_state(pipeline_.get(), GST_STATE_NULL);
    g_signal_handlers_disconnect_by_data(webrtc_.get(), this);
    if (rtpbin_) g_signal_handlers_disconnect_by_data(rtpbin_.get(), this);
    throw;
  }
}

void Session::negotiate(const std::string& offer, const WhepOfferChoice& format,
                        const WebRtcConfig& config) {
  // Host candidates on the configured addresses only: libnice then ignores every other
  // interface. No STUN or TURN server is set, so there are no other kinds of candidate.
  {
    GstWebRTCICE* raw = nullptr;
    g_object_get(webrtc_.get(), "ice-agent", &raw, nullptr);
    Ice ice = Ice::adopt(raw);
    for (const std::string& address : config.ice_addresses) {
      gboolean added = FALSE;
      g_signal_emit_by_name(ice.get(), "add-local-ip-address", address.c_str(), &added);
      if (!added) spdlog::warn("webrtc: ICE refused the local address {}", address);
    }
  }
  // The transceiver the payloader's pad made sends only, with the offer's own H.264 format
  // as its codec preference: the answer is made before any frame (and so any caps) has gone
  // through the pad.
  {
    GstWebRTCRTPTransceiver* raw = nullptr;
    g_signal_emit_by_name(webrtc_.get(), "get-transceiver", 0, &raw);
    Transceiver trans = Transceiver::adopt(raw);
    if (!trans) throw WebRtcError("webrtc: webrtcbin made no transceiver for the stream");
    auto caps = gst::Caps::adopt(gst_caps_from_string(rtp_caps(format).c_str()));
    g_object_set(trans.get(), "codec-preferences", caps.get(), "direction",
                 GST_WEBRTC_RTP_TRANSCEIVER_DIRECTION_SENDONLY, nullptr);
  }
  if (gst_element_set_state(pipeline_.get(), GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw WebRtcError("webrtc: the session pipeline does not start");

  GstSDPMessage* sdp = nullptr;
  gst_sdp_message_new(&sdp);
  if (gst_sdp_message_parse_buffer(reinterpret_cast<const guint8*>(offer.data()),
                                   static_cast<guint>(offer.size()), sdp) != GST_SDP_OK) {
    gst_sdp_message_free(sdp);
    throw WhepOfferError("the SDP does not parse");
  }
  Description remote =
      Description::adopt(gst_webrtc_session_description_new(GST_WEBRTC_SDP_TYPE_OFFER, sdp));
  {
    Call call;
    g_signal_emit_by_name(webrtc_.get(), "set-remote-description", remote.get(), call.promise());
    call.wait("the offer");
  }
  Description answer;
  {
    Call call;
    g_signal_emit_by_name(webrtc_.get(), "create-answer", nullptr, call.promise());
    const GstStructure* reply = call.wait("the answer");
    GstWebRTCSessionDescription* raw = nullptr;
    if (reply)
      gst_structure_get(reply, "answer", GST_TYPE_WEBRTC_SESSION_DESCRIPTION, &raw, nullptr);
    answer = Description::adopt(raw);
    if (!answer) throw WhepOfferError("webrtcbin made no answer to the offer");
  }
  {
    Call call;
    g_signal_emit_by_name(webrtc_.get(), "set-local-description", answer.get(), call.promise());
    call.wait("the answer as local description");
  }
  {
    std::unique_lock lock(gather_mutex_);
    if (!gathered_cv_.wait_for(lock, std::chrono::milliseconds(config.gather_timeout_ms),
                               [&] { return gathered_; }))
      throw WebRtcError(
          fmt::format("webrtc: ICE gathering not complete after {} ms", config.gather_timeout_ms));
  }
  // The local description now carries the gathered candidates.
  GstWebRTCSessionDescription* raw = nullptr;
  g_object_get(webrtc_.get(), "local-description", &raw, nullptr);
  Description local = Description::adopt(raw);
  if (!local) throw WebRtcError("webrtc: no local description after the answer");
  gchar* text = gst_sdp_message_as_text(local.get()->sdp);
  answer_ = text;
  g_free(text);
  answered_ns_ = monotonic_now_ns();
}

Session::~Session() {
  gst_element_set_state(pipeline_.get(), GST_STATE_NULL);
  g_signal_handlers_disconnect_by_data(webrtc_.get(), this);
  if (rtpbin_) g_signal_handlers_disconnect_by_data(rtpbin_.get(), this);
}

void Session::on_rtcp() {
  last_heard_ns_ = monotonic_now_ns();
}

void Session::on_bye() {
  bye_ = true;
  if (hooks_.changed) hooks_.changed();
}

void Session::on_ice_state() {
  GstWebRTCICEConnectionState state{};
  g_object_get(webrtc_.get(), "ice-connection-state", &state, nullptr);
  ice_state_ = static_cast<int>(state);
  if (state == GST_WEBRTC_ICE_CONNECTION_STATE_CONNECTED ||
      state == GST_WEBRTC_ICE_CONNECTION_STATE_COMPLETED) {
    if (!ever_connected_) connected_ns_ = monotonic_now_ns();
    ever_connected_ = true;
    disconnected_ns_ = 0;
  } else if (state == GST_WEBRTC_ICE_CONNECTION_STATE_DISCONNECTED) {
    disconnected_ns_ = monotonic_now_ns();
  }
  if (hooks_.changed) hooks_.changed();
}

void Session::on_gathering_state() {
  GstWebRTCICEGatheringState state{};
  g_object_get(webrtc_.get(), "ice-gathering-state", &state, nullptr);
  if (state != GST_WEBRTC_ICE_GATHERING_STATE_COMPLETE) return;
  std::lock_guard lock(gather_mutex_);
  gathered_ = true;
  gathered_cv_.notify_all();
}

void Session::push(GstBuffer* access_unit, TimestampNs capture_ns) {
  if (answered_ns_ == 0) return;
  auto* src = GST_APP_SRC(src_.get());
  if (gst_app_src_get_current_level_bytes(src) > kMaxQueuedBytes) {
    if (!need_keyframe_) hooks_.keyframe_wanted();
    need_keyframe_ = true;
    return;
  }
  if (need_keyframe_ && GST_BUFFER_FLAG_IS_SET(access_unit, GST_BUFFER_FLAG_DELTA_UNIT)) return;
  need_keyframe_ = false;
  const GstClockTime base = gst_element_get_base_time(pipeline_.get());
  GstBuffer* buffer = gst_buffer_copy(access_unit);  // shares the memory, not the bytes
  const auto at = static_cast<GstClockTime>(capture_ns);
  GST_BUFFER_PTS(buffer) = at > base ? at - base : 0;
  GST_BUFFER_DTS(buffer) = GST_BUFFER_PTS(buffer);  // no B-frames: decode order is show order
  if (gst_app_src_push_buffer(src, buffer) == GST_FLOW_OK) ++sent_;
}

std::string Session::error() {
  if (failed_.empty()) {
    auto bus = gst::Bus::adopt(gst_element_get_bus(pipeline_.get()));
    while (GstMessage* raw = gst_bus_pop_filtered(bus.get(), GST_MESSAGE_ERROR)) {
      GError* err = nullptr;
      gchar* debug = nullptr;
      gst_message_parse_error(raw, &err, &debug);
      failed_ = fmt::format("{} ({})", err ? err->message : "error", debug ? debug : "");
      if (err) g_error_free(err);
      g_free(debug);
      gst_message_unref(raw);
    }
  }
  return failed_;
}

bool Session::finished(TimestampNs now, TimestampNs connect_timeout,
                       TimestampNs disconnected_timeout) {
  if (!error().empty() || bye_) return true;
  const int state = ice_state_;
  if (state == GST_WEBRTC_ICE_CONNECTION_STATE_FAILED ||
      state == GST_WEBRTC_ICE_CONNECTION_STATE_CLOSED)
    return true;
  if (!ever_connected_) return answered_ns_ != 0 && now - answered_ns_ > connect_timeout;
  const TimestampNs since = disconnected_ns_;
  if (since != 0 && now - since > disconnected_timeout) return true;
  // Silent: no RTCP for as long (counted from the connection when none came yet).
  const TimestampNs heard = std::max<TimestampNs>(last_heard_ns_, connected_ns_);
  return now - heard > disconnected_timeout;
}

}  // namespace probeless::webrtc
