#pragma once
// The HTTP server's insides, shared by http_server.cpp (the event loop, streams, the
// slow-client policy) and http_routes.cpp (the one-shot answers: snapshot, status, state,
// metrics, OPTIONS). Private to app/outputs: nothing else includes it.
#include <event2/buffer.h>
#include <event2/event.h>
#include <event2/http.h>
#include <event2/listener.h>

#include <deque>
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/outputs/http_compat.hpp"
#include "app/outputs/http_connections.hpp"
#include "app/outputs/http_server.hpp"
#include "app/outputs/whep_endpoint.hpp"
#include "app/service/heartbeat.hpp"
#include "base/latest_frame.hpp"
#include "base/stage_stats.hpp"

namespace probeless {

// ustreamer's placeholder size before any frame has told us the real one (its default).
inline constexpr int kPlaceholderWidth = 640;
inline constexpr int kPlaceholderHeight = 480;
// What every route accepts (ustreamer's set); the rest get 405.
inline constexpr const char* kAllowed = "GET, HEAD, OPTIONS";

// Lets clients share one JPEG without a copy: the evbuffer holds a reference to the bytes
// and a heap-held shared_ptr that keeps them alive until libevent has written them.
inline void add_jpeg_reference(evbuffer* buf,
                               const std::shared_ptr<const std::vector<std::uint8_t>>& jpeg) {
  auto* keep = new std::shared_ptr<const std::vector<std::uint8_t>>(jpeg);
  evbuffer_add_reference(
      buf, jpeg->data(), jpeg->size(),
      [](const void*, size_t, void* arg) {
        delete static_cast<std::shared_ptr<const std::vector<std::uint8_t>>*>(arg);
      },
      keep);
}

struct StreamClient {
  HttpServer::Impl* server = nullptr;
  evhttp_request* request = nullptr;  // null once libevent has finished with it
  std::string peer;                   // "address:port"
  std::string peer_address;           // for the per-address stream cap
  std::string id;                     // ustreamer's client id in /state
  StreamOptions options;              // from the stream URL's query
  RateMeter sent_rate;                // frames sent, for X-UStreamer-Client-FPS and /state
  TimestampNs connected_ns = 0;
  LatestFrame<EncodedFrame>::Sequence last_sent = 0;
  std::uint64_t frames_sent = 0;
  std::uint64_t skipped = 0;  // frames between two sent ones
  std::size_t buffered = 0;   // output not yet taken by the kernel, as of the last look
  // The slow-reader rule (stalled_client_timeout): every byte our output buffer ever took for
  // this client, chunk framing included, and for each part not yet handed whole to the
  // kernel, that count just after it and when it was queued. The buffer is a FIFO: a part is
  // out once fewer bytes remain in it than were added after the part.
  std::uint64_t bytes_added = 0;
  std::deque<std::pair<std::uint64_t, TimestampNs>> queued_parts;
};

// A WHEP answer in the making: the request waits for the WebRTC output's callback.
struct PendingWhep {
  HttpServer::Impl* server = nullptr;
  std::uint64_t key = 0;
  evhttp_request* request = nullptr;  // null once its connection has closed
  std::string location_base;          // the POST's path: Location is it + "/" + session id
};

// Where the WebRTC output's callbacks leave answers; shared with them, so a callback that
// comes after the server stopped finds `wake` null and drops its answer.
struct WhepMailbox {
  std::mutex mutex;
  event* wake = nullptr;
  std::vector<std::pair<std::uint64_t, WhepAnswer>> done;
};

struct HttpServer::Impl {
  HttpServerConfig config;
  StatusCallback status;
  LatestFrame<EncodedFrame> frames;

  event_base* base = nullptr;
  evhttp* http = nullptr;
  event* frame_event = nullptr;
  event* stop_event = nullptr;
  event* resume_accept_event = nullptr;  // re-enables the listener after an accept failure
  evconnlistener* listener = nullptr;
  std::unique_ptr<HttpConnections> connections;
  int port = 0;
  std::thread thread;

  std::mutex wake_mutex;  // publish() and stop(): the events exist while `running`
  bool running = false;

  // The server thread's state; stats_mutex guards what stats() reads from other threads.
  std::optional<LatestFrame<EncodedFrame>::Item> current;
  JpegSize current_size;            // read from the current frame's JPEG
  TimestampNs current_wall_ns = 0;  // its capture time on the wall clock, converted once
  std::shared_ptr<const std::vector<std::uint8_t>> placeholder;  // made at the first need
  std::uint64_t next_client_id = 0;
  RateMeter published_rate;  // frames handed to publish(): /state's queued_fps
  std::list<std::unique_ptr<StreamClient>> clients;
  mutable std::mutex stats_mutex;
  std::uint64_t requests = 0;
  std::uint64_t refused = 0;
  std::uint64_t accept_failures = 0;
  std::uint64_t slow_streams_dropped = 0;
  HttpConnectionCounts connection_counts;  // a copy for stats(), updated each sweep
  std::uint64_t bytes_queued = 0;          // every response body and stream part
  std::uint64_t bytes_dropped = 0;         // queued to clients that closed before taking it
  Heartbeat heartbeat;                     // beaten on the server thread by watch()'s timer

  // WHEP (http_whep.cpp): the endpoint, set after start; answers pending on the server thread.
  std::mutex whep_mutex;
  std::shared_ptr<WhepEndpoint> whep;
  std::shared_ptr<WhepMailbox> whep_mailbox = std::make_shared<WhepMailbox>();
  event* whep_event = nullptr;
  std::map<std::uint64_t, std::unique_ptr<PendingWhep>> whep_pending;
  std::uint64_t next_whep = 0;

  void setup();
  void teardown();
  void on_request(evhttp_request* req);
  void on_frame();
  void on_accept_error();
  bool admit(evhttp_request* req);
  void serve_stream(evhttp_request* req);
  void serve_snapshot(evhttp_request* req);
  void serve_status(evhttp_request* req);
  void serve_state(evhttp_request* req);
  void serve_metrics(evhttp_request* req);
  void serve_options(evhttp_request* req);
  // `resource`: a session's URL (DELETE), else the endpoint (POST); `path` as requested.
  void serve_whep(evhttp_request* req, bool resource, std::string_view path);
  void set_whep(std::shared_ptr<WhepEndpoint> endpoint);
  std::shared_ptr<WhepEndpoint> whep_endpoint();
  void on_whep_done();
  void whep_connection_closed(PendingWhep& pending);
  void drop_pending_whep();  // teardown: the requests freed, late answers dropped
  void add_frame_headers(evhttp_request* req);
  // What ustreamer reports of the source: live (a frame that is not a NO SIGNAL repeat) and
  // the size shown (the placeholder's before the first frame).
  bool source_online() const { return current && !current->value.no_signal; }
  JpegSize shown_size() const {
    return current ? current_size : JpegSize{kPlaceholderWidth, kPlaceholderHeight};
  }
  // 200 with the text `make` builds, or 500 naming `what` if building it throws (no exception
  // may reach libevent).
  void send_built(evhttp_request* req, const char* what, const char* content_type,
                  const std::function<std::string()>& make);
  void add_common_headers(evkeyvalq* headers, const char* content_type);
  void send_body(evhttp_request* req, int code, const char* reason, const char* content_type,
                 evbuffer* body);
  void send_text(evhttp_request* req, int code, const char* reason, const std::string& text);
  // The placeholder JPEG (made at the first need); false if it could not be made.
  bool make_placeholder(std::string* problem = nullptr);
  void offer(StreamClient& client);
  // One multipart part to `client`: `jpeg` with the headers `frame` describes; the newest
  // frame's sequence (0 for the placeholder) is what the client has seen.
  void send_part(StreamClient& client, const std::shared_ptr<const std::vector<std::uint8_t>>& jpeg,
                 const PartFrame& frame, std::uint64_t sequence);
  void drained(StreamClient& client);
  void drop_slow_streams();
  void remove(StreamClient* client);
  HttpServerStats stats() const;
};

}  // namespace probeless
