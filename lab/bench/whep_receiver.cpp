#include "lab/bench/whep_receiver.hpp"

#define GST_USE_UNSTABLE_API  // gst/webrtc is marked unstable in 1.22
#include <arpa/inet.h>
#include <gst/app/gstappsink.h>
#include <gst/sdp/sdp.h>
#include <gst/webrtc/webrtc.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <memory>
#include <stdexcept>
#include <thread>

namespace probeless::lab {
namespace {

using Description = gst::Ref<GstWebRTCSessionDescription, gst_webrtc_session_description_free>;
using Promise = gst::Ref<GstPromise, gst_promise_unref>;

struct HttpReply {
  int status = 0;
  std::string location;
  std::string body;
};

// One HTTP/1.0 request over loopback, read to the server's close. The answer is bounded
// (an SDP answer is a few KB) before it is kept.
HttpReply http_call(int port, const std::string& method, const std::string& path,
                    const std::string& body) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error("whep receiver: socket");
  std::unique_ptr<int, void (*)(int*)> guard(new int(fd), [](int* f) {
    ::close(*f);
    delete f;
  });
  const timeval five{5, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &five, sizeof five);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
    throw std::runtime_error("whep receiver: cannot connect to port " + std::to_string(port));
  std::string request = method + " " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\n";
  if (!body.empty())
    request +=
        "Content-Type: application/sdp\r\nContent-Length: " + std::to_string(body.size()) + "\r\n";
  request += "\r\n" + body;
  if (::send(fd, request.data(), request.size(), MSG_NOSIGNAL) !=
      static_cast<ssize_t>(request.size()))
    throw std::runtime_error("whep receiver: send");
  std::string raw;
  char buf[4096];
  while (raw.size() < 256 * 1024) {
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    raw.append(buf, static_cast<std::size_t>(n));
  }
  HttpReply reply;
  const auto head_end = raw.find("\r\n\r\n");
  if (raw.compare(0, 5, "HTTP/") != 0 || head_end == std::string::npos)
    throw std::runtime_error("whep receiver: no HTTP answer to " + method + " " + path);
  reply.status = std::atoi(raw.c_str() + raw.find(' ') + 1);
  const std::string head = raw.substr(0, head_end);
  for (std::size_t at = head.find("\r\n"); at != std::string::npos;
       at = head.find("\r\n", at + 2)) {
    const std::string line = head.substr(at + 2, head.find("\r\n", at + 2) - at - 2);
    if (line.size() > 10 && strncasecmp(line.c_str(), "location: ", 10) == 0)
      reply.location = line.substr(10);
  }
  reply.body = raw.substr(head_end + 4);
  return reply;
}

// A webrtcbin action signal with a promise; the reply (owned by the promise).
const GstStructure* call(GstElement* webrtc, const char* signal, gpointer arg, Promise& promise) {
  promise = Promise::adopt(gst_promise_new());
  g_signal_emit_by_name(webrtc, signal, arg, promise.get());
  if (gst_promise_wait(promise.get()) != GST_PROMISE_RESULT_REPLIED)
    throw std::runtime_error(std::string("whep receiver: no reply to ") + signal);
  return gst_promise_get_reply(promise.get());
}

void pad_added_cb(GstElement*, GstPad* pad, gpointer self) {
  static_cast<WhepReceiver*>(self)->on_pad_added(pad);
}

struct Gathered {
  std::mutex mutex;
  std::condition_variable cv;
  bool done = false;
};

void gathering_cb(GstElement* webrtc, GParamSpec*, gpointer data) {
  GstWebRTCICEGatheringState state{};
  g_object_get(webrtc, "ice-gathering-state", &state, nullptr);
  if (state != GST_WEBRTC_ICE_GATHERING_STATE_COMPLETE) return;
  auto* g = static_cast<Gathered*>(data);
  std::lock_guard lock(g->mutex);
  g->done = true;
  g->cv.notify_all();
}

}  // namespace

WhepReceiver::WhepReceiver(int http_port, const std::string& path) : port_(http_port) {
  gst::ensure_gstreamer();
  pipeline_ = gst::Element::adopt_sink(gst_pipeline_new("whep-receiver"));
  GstElement* webrtc = gst_element_factory_make("webrtcbin", "webrtc");
  if (!webrtc)
    throw std::runtime_error(
        "whep receiver: no webrtcbin (install gstreamer1.0-plugins-bad and gstreamer1.0-nice)");
  g_object_set(webrtc, "bundle-policy", GST_WEBRTC_BUNDLE_POLICY_MAX_BUNDLE, "latency", 0u,
               nullptr);
  gst_bin_add(GST_BIN(pipeline_.get()), webrtc);  // the bin takes the floating reference
  webrtc_ = gst::Element::share(webrtc);
  {
    GstWebRTCICE* ice = nullptr;
    g_object_get(webrtc_.get(), "ice-agent", &ice, nullptr);
    gboolean added = FALSE;
    g_signal_emit_by_name(ice, "add-local-ip-address", "127.0.0.1", &added);
    gst_object_unref(ice);
  }
  g_signal_connect(webrtc_.get(), "pad-added", G_CALLBACK(pad_added_cb), this);
  Gathered gathered;
  const gulong gather_handler = g_signal_connect(webrtc_.get(), "notify::ice-gathering-state",
                                                 G_CALLBACK(gathering_cb), &gathered);
  auto caps = gst::Caps::adopt(gst_caps_from_string(
      "application/x-rtp,media=video,encoding-name=H264,clock-rate=90000,payload=96,"
      "packetization-mode=(string)1,profile-level-id=(string)42e01f"));
  GstWebRTCRTPTransceiver* trans = nullptr;
  g_signal_emit_by_name(webrtc_.get(), "add-transceiver",
                        GST_WEBRTC_RTP_TRANSCEIVER_DIRECTION_RECVONLY, caps.get(), &trans);
  if (trans) gst_object_unref(trans);
  if (gst_element_set_state(pipeline_.get(), GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw std::runtime_error("whep receiver: webrtcbin does not start");

  Promise promise;
  const GstStructure* reply = call(webrtc_.get(), "create-offer", nullptr, promise);
  GstWebRTCSessionDescription* offer_raw = nullptr;
  if (reply)
    gst_structure_get(reply, "offer", GST_TYPE_WEBRTC_SESSION_DESCRIPTION, &offer_raw, nullptr);
  const Description offer = Description::adopt(offer_raw);
  if (!offer) throw std::runtime_error("whep receiver: webrtcbin made no offer");
  call(webrtc_.get(), "set-local-description", offer.get(), promise);
  {
    std::unique_lock lock(gathered.mutex);
    gathered.cv.wait_for(lock, std::chrono::seconds(5), [&] { return gathered.done; });
  }
  g_signal_handler_disconnect(webrtc_.get(), gather_handler);
  GstWebRTCSessionDescription* local_raw = nullptr;
  g_object_get(webrtc_.get(), "local-description", &local_raw, nullptr);
  const Description local = Description::adopt(local_raw);
  gchar* text = gst_sdp_message_as_text(local.get()->sdp);
  const std::string offer_sdp = text;
  g_free(text);

  const HttpReply answer = http_call(port_, "POST", path, offer_sdp);
  if (answer.status != 201)
    throw std::runtime_error("whep receiver: POST " + path + ": " + std::to_string(answer.status) +
                             " " + answer.body);
  location_ = answer.location;
  GstSDPMessage* sdp = nullptr;
  gst_sdp_message_new(&sdp);
  gst_sdp_message_parse_buffer(reinterpret_cast<const guint8*>(answer.body.data()),
                               static_cast<guint>(answer.body.size()), sdp);
  const Description remote =
      Description::adopt(gst_webrtc_session_description_new(GST_WEBRTC_SDP_TYPE_ANSWER, sdp));
  call(webrtc_.get(), "set-remote-description", remote.get(), promise);
  // RTCP every second, as browsers send it, not RTP's 5 s minimum: the service ends a session
  // whose client has been silent for [webrtc] disconnected_timeout_s.
  if (auto rtpbin = gst::Element::adopt(gst_bin_get_by_name(GST_BIN(webrtc_.get()), "rtpbin"))) {
    GObject* session = nullptr;
    g_signal_emit_by_name(rtpbin.get(), "get-session", 0u, &session);
    if (session) {
      g_object_set(session, "rtcp-min-interval", guint64{GST_SECOND}, nullptr);
      g_object_unref(session);
    }
  }
}

void WhepReceiver::on_pad_added(GstPad* pad) {
  if (GST_PAD_DIRECTION(pad) != GST_PAD_SRC) return;
  // The same decoder settings as the RTSP receiver (lab/bench/rtsp_receiver.cpp says why).
  GError* raw = nullptr;
  GstElement* bin = gst_parse_bin_from_description(
      "rtph264depay ! avdec_h264 output-corrupt=false thread-type=slice ! videoconvert "
      "! video/x-raw,format=RGB ! appsink name=sink sync=false max-buffers=4 drop=false",
      TRUE, &raw);
  if (raw) {
    g_error_free(raw);
    return;
  }
  gst_bin_add(GST_BIN(pipeline_.get()), bin);
  gst_element_sync_state_with_parent(bin);
  auto sink_pad =
      gst::Ref<GstPad, gst_object_unref>::adopt(gst_element_get_static_pad(bin, "sink"));
  gst_pad_link(pad, sink_pad.get());
  std::lock_guard lock(sink_mutex_);
  sink_ = gst::Element::adopt(gst_bin_get_by_name(GST_BIN(bin), "sink"));
}

WhepReceiver::~WhepReceiver() {
  if (pipeline_) gst_element_set_state(pipeline_.get(), GST_STATE_NULL);
  if (!location_.empty()) {
    try {
      http_call(port_, "DELETE", location_, "");
    } catch (const std::exception&) {
      // the service may be gone already; the session then ends with it
    }
  }
}

void WhepReceiver::vanish() {
  gst_element_set_state(pipeline_.get(), GST_STATE_NULL);
  location_.clear();
}

void WhepReceiver::throw_if_ended() {
  gst::throw_if_ended(pipeline_.get(), "whep receiver");
}

std::optional<ReceivedFrame> WhepReceiver::next(std::chrono::milliseconds timeout) {
  gst::Element sink;
  {
    std::lock_guard lock(sink_mutex_);
    if (sink_) sink = gst::Element::share(sink_.get());
  }
  if (!sink) {  // the stream's pad has not appeared yet
    std::this_thread::sleep_for(std::min(timeout, std::chrono::milliseconds(50)));
    throw_if_ended();
    return std::nullopt;
  }
  auto sample = gst::Sample::adopt(gst_app_sink_try_pull_sample(
      GST_APP_SINK(sink.get()), static_cast<GstClockTime>(timeout.count()) * GST_MSECOND));
  if (!sample) {
    throw_if_ended();
    return std::nullopt;
  }
  ReceivedFrame out;
  out.decoded_ns = monotonic_now_ns();
  out.image = gst::rgb_image_of(sample.get(), "whep receiver");
  return out;
}

}  // namespace probeless::lab
