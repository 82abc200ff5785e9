#include "app/outputs/rtsp_server.hpp"

#include <gst/app/gstappsrc.h>
#include <gst/rtsp-server/rtsp-server.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <mutex>
#include <regex>
#include <thread>

#include "app/outputs/gst_objects.hpp"
#include "app/outputs/h264_encoder.hpp"
#include "app/service/heartbeat.hpp"

namespace probeless {
namespace {

// Basic authentication for the one mount: the credentials give the role "viewer", which may
// open and play the media; a request without them gets 401 and a challenge (no default token,
// so anonymous clients have no role).
void require_basic_auth(GstRTSPServer* server, GstRTSPMediaFactory* factory,
                        const std::string& user, const std::string& password) {
  GstRTSPAuth* auth = gst_rtsp_auth_new();
  GstRTSPToken* token =
      gst_rtsp_token_new(GST_RTSP_TOKEN_MEDIA_FACTORY_ROLE, G_TYPE_STRING, "viewer", nullptr);
  gchar* basic = gst_rtsp_auth_make_basic(user.c_str(), password.c_str());
  gst_rtsp_auth_add_basic(auth, basic, token);
  g_free(basic);
  gst_rtsp_token_unref(token);
  gst_rtsp_server_set_auth(server, auth);
  g_object_unref(auth);
  gst_rtsp_media_factory_add_role(factory, "viewer", GST_RTSP_PERM_MEDIA_FACTORY_ACCESS,
                                  G_TYPE_BOOLEAN, TRUE, GST_RTSP_PERM_MEDIA_FACTORY_CONSTRUCT,
                                  G_TYPE_BOOLEAN, TRUE, nullptr);
}

using Server = gst::Ref<GstRTSPServer, g_object_unref>;
using MediaFactory = gst::Ref<GstRTSPMediaFactory, g_object_unref>;
using MountPoints = gst::Ref<GstRTSPMountPoints, g_object_unref>;
using SessionPool = gst::Ref<GstRTSPSessionPool, g_object_unref>;
using Media = gst::Ref<GstRTSPMedia, g_object_unref>;
using Clock = gst::Ref<GstClock, gst_object_unref>;

// The elements of the media, with the Debian package that ships each (the encoder's are
// checked by H264Encoder).
constexpr gst::RequiredElement kRequired[] = {{"appsrc", "gstreamer1.0-plugins-base"},
                                              {"rtph264pay", "gstreamer1.0-plugins-good"}};

// A player that stops reading (or a slow link) would otherwise queue access units without
// end; past this the media skips to the next keyframe. ~1 s of 2 Mbit/s.
constexpr guint64 kMaxQueuedBytes = 256 * 1024;

// What the media-factory callbacks, the encoder's subscription and push() share; the GLib
// callbacks hold it through a shared_ptr of their own, so a media thread finishing late
// never sees a freed server. The encoder is weak here: only the server owns it.
struct Feed {
  std::weak_ptr<H264Encoder> encoder;
  std::mutex mutex;
  Media media;                // the shared media while it is prepared (null: nobody watching)
  gst::Element appsrc;        // its source of access units
  bool need_keyframe = true;  // the media starts, or restarts after a drop, at a keyframe
  std::atomic<std::uint64_t> pushed{0}, sent{0}, no_client{0}, queue_full{0}, media_created{0},
      units{0}, keyframes{0};

  void request_keyframe() {
    if (auto e = encoder.lock(); e && e->request_keyframe()) ++keyframes;
  }
  // The encoder's thread: one access unit into the media, stamped in its running time.
  void on_access_unit(const H264AccessUnit& unit);
};
using FeedRef = std::shared_ptr<Feed>;

bool is_playing(GstElement* element) {
  GST_OBJECT_LOCK(element);
  const bool playing = GST_STATE(element) == GST_STATE_PLAYING;
  GST_OBJECT_UNLOCK(element);
  return playing;
}

void Feed::on_access_unit(const H264AccessUnit& unit) {
  std::lock_guard lock(mutex);
  GstElement* src = appsrc.get();
  if (!src || !is_playing(src)) {  // no media, or one not streaming: WebRTC's frame
    need_keyframe = true;
    return;
  }
  if (gst_app_src_get_current_level_bytes(GST_APP_SRC(src)) > kMaxQueuedBytes)
    need_keyframe = true;
  else if (need_keyframe && unit.keyframe)
    need_keyframe = false;
  if (need_keyframe) {  // a player could not decode a delta frame without its reference
    request_keyframe();
    return;
  }
  // The frame's capture time minus the media's base time, as the RGB frames were stamped
  // when the media had an encoder of its own: one clock (CLOCK_MONOTONIC) for both.
  const GstClockTime base = gst_element_get_base_time(src);
  const auto at = static_cast<GstClockTime>(unit.capture_ns);
  GstBuffer* buffer = gst_buffer_copy(unit.buffer);  // shares the memory, not the bytes
  GST_BUFFER_PTS(buffer) = at > base ? at - base : 0;
  GST_BUFFER_DTS(buffer) = GST_BUFFER_PTS(buffer);  // no B-frames: decode order is show order
  if (gst_app_src_push_buffer(GST_APP_SRC(src), buffer) == GST_FLOW_OK) ++units;
}

void delete_feed_ref(gpointer data, GClosure*) {
  delete static_cast<FeedRef*>(data);
}

void on_media_unprepared(GstRTSPMedia* media, gpointer data) {
  Feed& feed = **static_cast<FeedRef*>(data);
  std::lock_guard lock(feed.mutex);
  if (feed.media.get() != media) return;
  feed.media.reset();
  feed.appsrc.reset();
}

void on_media_configure(GstRTSPMediaFactory*, GstRTSPMedia* media, gpointer data) {
  const FeedRef& ref = *static_cast<FeedRef*>(data);
  auto bin = gst::Element::adopt(gst_rtsp_media_get_element(media));
  auto src = gst::Element::adopt(gst_bin_get_by_name_recurse_up(GST_BIN(bin.get()), "src"));
  if (!src) {
    spdlog::error("rtsp: the media has no appsrc named 'src'");
    return;
  }
  g_signal_connect_data(media, "unprepared", G_CALLBACK(on_media_unprepared), new FeedRef(ref),
                        delete_feed_ref, GConnectFlags{});
  ++ref->media_created;
  {
    std::lock_guard lock(ref->mutex);
    ref->media = Media::share(media);
    ref->appsrc = std::move(src);
    ref->need_keyframe = true;
  }
  // The media is prepared once its payloader has seen SPS/PPS: a keyframe now, not at the
  // next periodic one (up to keyframe_interval frames away when WebRTC keeps the encoder busy).
  ref->request_keyframe();
}

// A client joining the shared media mid-stream: its player can start only at a keyframe.
void on_play_request(GstRTSPClient*, GstRTSPContext*, gpointer data) {
  (*static_cast<FeedRef*>(data))->request_keyframe();
}

void on_client_connected(GstRTSPServer*, GstRTSPClient* client, gpointer data) {
  g_signal_connect_data(client, "play-request", G_CALLBACK(on_play_request),
                        new FeedRef(*static_cast<FeedRef*>(data)), delete_feed_ref,
                        GConnectFlags{});
}

gboolean quit_loop(gpointer loop) {
  g_main_loop_quit(static_cast<GMainLoop*>(loop));
  return G_SOURCE_REMOVE;
}

GstRTSPFilterResult remove_client(GstRTSPServer*, GstRTSPClient*, gpointer) {
  return GST_RTSP_FILTER_REMOVE;
}
GstRTSPFilterResult remove_session(GstRTSPSessionPool*, GstRTSPSession*, gpointer) {
  return GST_RTSP_FILTER_REMOVE;
}

}  // namespace

nlohmann::json to_json(const RtspServerStats& s) {
  return {{"url", s.url},
          {"encoder", s.encoder},
          {"clients", s.clients},
          {"media_created", s.media_created},
          {"frames_pushed", s.frames_pushed},
          {"frames_sent", s.frames_sent},
          {"dropped_no_client", s.dropped_no_client},
          {"dropped_queue_full", s.dropped_queue_full},
          {"access_units_sent", s.access_units_sent},
          {"keyframe_requests", s.keyframe_requests}};
}

void check_rtsp_path(const std::string& path) {
  static const std::regex valid("(/[A-Za-z0-9._-]+)+");
  static const std::regex dots("(^|/)\\.\\.?(/|$)");
  if (!std::regex_match(path, valid) || std::regex_search(path, dots))
    throw RtspServerError("rtsp: path '" + path +
                          "' must look like /name or /name/name (letters, digits, '.', '_', "
                          "'-'; not . or ..)");
}

struct RtspServer::Impl {
  RtspServerConfig config;
  std::shared_ptr<H264Encoder> encoder;
  FeedRef feed = std::make_shared<Feed>();
  H264Encoder::Subscription subscription;  // before `feed` goes: its callback uses it
  Server server;
  MediaFactory factory;
  gst::MainContext context;
  gst::MainLoop loop;
  gst::Source listener;
  int port = 0;
  std::thread thread;
  std::mutex stop_mutex;
  bool stopped = false;
  Heartbeat heartbeat;  // beaten on the loop's thread by watch()'s timeout source
  gst::Source heartbeat_source;
};

RtspServer::RtspServer(RtspServerConfig config, std::shared_ptr<H264Encoder> encoder)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.config = std::move(config);
  const RtspServerConfig& c = m.config;
  check_rtsp_path(c.path);
  if (c.port < 0 || c.port > 65535) throw RtspServerError("rtsp: port out of range");
  gst::ensure_gstreamer();
  if (const std::string missing = gst::missing_element(kRequired); !missing.empty())
    throw RtspServerError("rtsp: " + missing);
  m.encoder = encoder ? std::move(encoder) : std::make_shared<H264Encoder>(c);
  m.feed->encoder = m.encoder;
  m.subscription = m.encoder->subscribe(
      [feed = m.feed.get()](const H264AccessUnit& u) { feed->on_access_unit(u); });

  // The encoder's access units as they come: SPS/PPS go in-band before every keyframe
  // (config-interval=-1), so a player joining the shared media starts at the next one.
  // rtph264pay takes the byte-stream as is (no h264parse: RTSP alone needs no plugins-bad).
  const std::string launch =
      "( appsrc name=src is-live=true format=time do-timestamp=false block=false "
      "caps=video/x-h264,stream-format=byte-stream,alignment=au "
      "! rtph264pay name=pay0 pt=96 config-interval=-1 )";
  m.factory = MediaFactory::adopt(gst_rtsp_media_factory_new());
  gst_rtsp_media_factory_set_launch(m.factory.get(), launch.c_str());
  gst_rtsp_media_factory_set_shared(m.factory.get(), TRUE);
  // The system clock is CLOCK_MONOTONIC, the clock the frames are stamped with: a frame's
  // capture time minus the media's base time is its running time.
  Clock clock = Clock::adopt(gst_system_clock_obtain());
  gst_rtsp_media_factory_set_clock(m.factory.get(), clock.get());
  g_signal_connect_data(m.factory.get(), "media-configure", G_CALLBACK(on_media_configure),
                        new FeedRef(m.feed), delete_feed_ref, GConnectFlags{});

  m.server = Server::adopt(gst_rtsp_server_new());
  g_signal_connect_data(m.server.get(), "client-connected", G_CALLBACK(on_client_connected),
                        new FeedRef(m.feed), delete_feed_ref, GConnectFlags{});
  gst_rtsp_server_set_address(m.server.get(), c.address.c_str());
  gst_rtsp_server_set_service(m.server.get(), std::to_string(c.port).c_str());
  {
    auto sessions = SessionPool::adopt(gst_rtsp_server_get_session_pool(m.server.get()));
    gst_rtsp_session_pool_set_max_sessions(sessions.get(), static_cast<guint>(c.max_sessions));
  }
  if (!c.user.empty()) require_basic_auth(m.server.get(), m.factory.get(), c.user, c.password);
  {
    auto mounts = MountPoints::adopt(gst_rtsp_server_get_mount_points(m.server.get()));
    gst_rtsp_mount_points_add_factory(
        mounts.get(), c.path.c_str(),
        static_cast<GstRTSPMediaFactory*>(g_object_ref(m.factory.get())));
  }
  GError* raw_error = nullptr;
  m.listener =
      gst::Source::adopt(gst_rtsp_server_create_source(m.server.get(), nullptr, &raw_error));
  if (!m.listener) {
    std::unique_ptr<GError, gst::ErrorDeleter> error(raw_error);
    throw RtspServerError(fmt::format("rtsp: cannot listen on {}:{}: {}", c.address, c.port,
                                      error ? error->message : "no reason given"));
  }
  m.port = gst_rtsp_server_get_bound_port(m.server.get());
  m.context = gst::MainContext::adopt(g_main_context_new());
  g_source_attach(m.listener.get(), m.context.get());
  m.loop = gst::MainLoop::adopt(g_main_loop_new(m.context.get(), FALSE));
  m.thread = std::thread([&m] {
    // Clients accepted here are handed to gst-rtsp-server's own thread pool.
    g_main_context_push_thread_default(m.context.get());
    g_main_loop_run(m.loop.get());
    g_main_context_pop_thread_default(m.context.get());
  });
  spdlog::info("rtsp: serving {} (H.264 by {}, {} kbit/s, keyframe every {} frames)", url(),
               m.encoder->name(), c.bitrate_kbps, c.keyframe_interval);
}

RtspServer::~RtspServer() {
  stop();
}

int RtspServer::port() const {
  return impl_->port;
}

std::string RtspServer::url() const {
  const std::string& a = impl_->config.address;
  const std::string host = a.find(':') != std::string::npos ? "[" + a + "]" : a;
  return fmt::format("rtsp://{}:{}{}", host, impl_->port, impl_->config.path);
}

std::string RtspServer::encoder_name() const {
  return impl_->encoder->name();
}

std::shared_ptr<H264Encoder> RtspServer::encoder() const {
  return impl_->encoder;
}

void RtspServer::push(std::shared_ptr<const ImageRGB8> frame, TimestampNs capture_ns) {
  Impl& m = *impl_;
  Feed& feed = *m.feed;
  ++feed.pushed;
  if (!frame || frame->empty()) return;
  {
    std::lock_guard lock(feed.mutex);
    // No media, or one prepared but paused: the encoder is left to WebRTC's clients, if any.
    if (!feed.appsrc || !is_playing(feed.appsrc.get())) {
      ++feed.no_client;
      return;
    }
  }
  switch (m.encoder->push(std::move(frame), capture_ns)) {
    case H264Encoder::Fed::Sent:
      ++feed.sent;
      break;
    case H264Encoder::Fed::QueueFull:
      ++feed.queue_full;
      break;
    case H264Encoder::Fed::Stopped:
      ++feed.no_client;
      break;
  }
}

void RtspServer::stop() {
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.stop_mutex);
    if (m.stopped) return;
    m.stopped = true;
  }
  // No access unit comes in after this (a shared encoder goes on for WebRTC). Then close the
  // connections and their sessions, then the media: its pipeline is in NULL and its threads
  // have stopped when unprepare returns.
  m.subscription.reset();
  gst_rtsp_server_client_filter(m.server.get(), remove_client, nullptr);
  {
    auto sessions = SessionPool::adopt(gst_rtsp_server_get_session_pool(m.server.get()));
    if (sessions) gst_rtsp_session_pool_filter(sessions.get(), remove_session, nullptr);
  }
  Media media;
  {
    std::lock_guard lock(m.feed->mutex);
    media = std::move(m.feed->media);
    m.feed->appsrc.reset();
  }
  if (media) gst_rtsp_media_unprepare(media.get());
  g_source_destroy(m.listener.get());
  // Quit from inside the loop: g_main_loop_quit() before the thread reached
  // g_main_loop_run() would be forgotten and the join would wait for ever.
  auto quit = gst::Source::adopt(g_idle_source_new());
  g_source_set_callback(quit.get(), quit_loop, m.loop.get(), nullptr);
  g_source_attach(quit.get(), m.context.get());
  if (m.thread.joinable()) m.thread.join();
  if (m.heartbeat_source) g_source_destroy(m.heartbeat_source.get());
  m.heartbeat = {};  // stopped on purpose: no longer watched
  spdlog::info("rtsp: stopped ({} frames sent)", m.feed->sent.load());
}

void RtspServer::add_status(nlohmann::json& status) const {
  status["rtsp"] = to_json(stats());
  status["h264"] = to_json(impl_->encoder->stats());
}

RtspServerStats RtspServer::stats() const {
  const Impl& m = *impl_;
  RtspServerStats s;
  s.url = url();
  s.encoder = m.encoder->name();
  GList* clients = gst_rtsp_server_client_filter(m.server.get(), nullptr, nullptr);
  s.clients = static_cast<int>(g_list_length(clients));
  g_list_free_full(clients, g_object_unref);
  const Feed& f = *m.feed;
  s.media_created = f.media_created;
  s.frames_pushed = f.pushed;
  s.frames_sent = f.sent;
  s.dropped_no_client = f.no_client;
  s.dropped_queue_full = f.queue_full;
  s.access_units_sent = f.units;
  s.keyframe_requests = f.keyframes;
  return s;
}

namespace {

gboolean on_heartbeat(gpointer heartbeat) {
  static_cast<Heartbeat*>(heartbeat)->beat();
  return G_SOURCE_CONTINUE;
}

}  // namespace

void RtspServer::watch(HeartbeatRegistry& heartbeats) {
  Impl& m = *impl_;
  std::lock_guard lock(m.stop_mutex);
  if (m.stopped || m.heartbeat_source) return;
  m.heartbeat = heartbeats.add("rtsp");
  m.heartbeat_source = gst::Source::adopt(g_timeout_source_new(250));
  g_source_set_callback(m.heartbeat_source.get(), on_heartbeat, &m.heartbeat, nullptr);
  g_source_attach(m.heartbeat_source.get(), m.context.get());
}

}  // namespace probeless
