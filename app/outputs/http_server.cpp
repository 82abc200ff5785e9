#include "app/outputs/http_server.hpp"

#include <event2/buffer.h>
#include <event2/bufferevent.h>
#include <event2/event.h>
#include <event2/http.h>
#include <event2/keyvalq_struct.h>
#include <event2/listener.h>
#include <event2/thread.h>
#include <fcntl.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <deque>
#include <list>
#include <map>
#include <mutex>
#include <optional>
#include <string_view>
#include <system_error>
#include <thread>

#include "app/outputs/http_server_impl.hpp"
#include "app/outputs/viewer_page.hpp"
#include "app/outputs/whep_offer.hpp"

namespace probeless {
namespace {

constexpr const char* kBoundary = kStreamBoundary;
constexpr const char* kNoCache =
    "no-store, no-cache, must-revalidate, proxy-revalidate, pre-check=0, post-check=0, "
    "max-age=0";
// A stream connection reads nothing after its request; this bounds what a client that
// keeps sending anyway can make us buffer.
constexpr std::size_t kStreamInputLimit = std::size_t{64} * 1024;

enum class Route { Index, Stream, Snapshot, Status, State, Metrics, Whep, WhepResource, NotFound };

// "" or "/name": the prefix a WHEP URL may have (mediamtx serves /<path>/whep).
bool whep_prefix(std::string_view p) {
  if (p.empty()) return true;
  if (p.front() != '/' || p.size() == 1) return false;
  return std::all_of(p.begin() + 1, p.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
  });
}

Route whep_route(std::string_view path) {
  constexpr std::string_view kWhep = "/whep";
  if (path.size() >= kWhep.size() && path.substr(path.size() - kWhep.size()) == kWhep)
    return whep_prefix(path.substr(0, path.size() - kWhep.size())) ? Route::Whep : Route::NotFound;
  const auto slash = path.rfind('/');
  const std::string_view id = path.substr(slash + 1);
  if (slash == std::string_view::npos || id.empty() || id.size() > 64 ||
      !std::all_of(id.begin(), id.end(),
                   [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); }))
    return Route::NotFound;
  return whep_route(path.substr(0, slash)) == Route::Whep ? Route::WhepResource : Route::NotFound;
}

Route route_for(std::string_view path, const char* query) {
  if (path == "/stream") return Route::Stream;
  if (path == "/snapshot") return Route::Snapshot;
  if (path == "/status") return Route::Status;
  if (path == "/state") return Route::State;
  if (path == "/metrics") return Route::Metrics;
  if (path != "/") return whep_route(path);
  if (query == nullptr || *query == '\0') return Route::Index;
  // mjpg-streamer's URLs: /?action=stream, /?action=snapshot.
  evkeyvalq params{};
  Route route = Route::Index;
  if (evhttp_parse_query_str(query, &params) == 0) {
    if (const char* action = evhttp_find_header(&params, "action")) {
      const std::string_view a(action);
      route = a == "stream" ? Route::Stream : a == "snapshot" ? Route::Snapshot : Route::NotFound;
    }
  }
  evhttp_clear_headers(&params);
  return route;
}

int open_listener(const std::string& address, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICHOST | AI_NUMERICSERV | AI_PASSIVE;
  addrinfo* found = nullptr;
  const std::string where = address + ":" + std::to_string(port);
  const std::string service = std::to_string(port);
  if (const int rc = getaddrinfo(address.c_str(), service.c_str(), &hints, &found); rc != 0) {
    throw HttpServerError("HTTP " + where + ": " + gai_strerror(rc));
  }
  std::unique_ptr<addrinfo, decltype(&freeaddrinfo)> guard(found, freeaddrinfo);
  const int fd = socket(found->ai_family, found->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) throw HttpServerError("HTTP " + where + ": socket: " + std::strerror(errno));
  const int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (bind(fd, found->ai_addr, found->ai_addrlen) != 0 || listen(fd, 64) != 0) {
    const int err = errno;
    close(fd);
    throw HttpServerError("HTTP " + where + ": " + std::strerror(err));
  }
  return fd;
}

int bound_port(int fd) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  if (getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) return 0;
  if (addr.ss_family == AF_INET) return ntohs(reinterpret_cast<sockaddr_in*>(&addr)->sin_port);
  if (addr.ss_family == AF_INET6) return ntohs(reinterpret_cast<sockaddr_in6*>(&addr)->sin6_port);
  return 0;
}

}  // namespace

namespace {

void on_request_cb(evhttp_request* req, void* arg) {
  static_cast<HttpServer::Impl*>(arg)->on_request(req);
}
void on_frame_cb(evutil_socket_t, short, void* arg) {
  static_cast<HttpServer::Impl*>(arg)->on_frame();
}
// The listener is evhttp's: its error callback gets evhttp's argument, not ours, so the
// server is found by its listener.
std::mutex g_listeners_mutex;
std::map<evconnlistener*, HttpServer::Impl*> g_listeners;

void on_accept_error_cb(evconnlistener* listener, void*) {
  HttpServer::Impl* server = nullptr;
  {
    std::lock_guard lock(g_listeners_mutex);
    if (auto it = g_listeners.find(listener); it != g_listeners.end()) server = it->second;
  }
  if (server) server->on_accept_error();
}
void on_resume_accept_cb(evutil_socket_t, short, void* arg) {
  evconnlistener_enable(static_cast<HttpServer::Impl*>(arg)->listener);
}
void on_whep_done_cb(evutil_socket_t, short, void* arg) {
  static_cast<HttpServer::Impl*>(arg)->on_whep_done();
}
void on_stop_cb(evutil_socket_t, short, void* arg) {
  event_base_loopbreak(static_cast<HttpServer::Impl*>(arg)->base);
}
// The client's output has drained: the moment to send the newest frame if it was skipped.
void on_stream_drained_cb(evhttp_connection*, void* arg) {
  auto* client = static_cast<StreamClient*>(arg);
  client->server->drained(*client);
}
// libevent is about to free the request it owned (a reply that ended normally).
void on_stream_complete_cb(evhttp_request*, void* arg) {
  static_cast<StreamClient*>(arg)->request = nullptr;
}
void on_stream_closed_cb(evhttp_connection*, void* arg) {
  auto* client = static_cast<StreamClient*>(arg);
  client->server->remove(client);
}

std::once_flag g_threads_once;

}  // namespace

void HttpServer::Impl::setup() {
  // event_active() from the publishing thread needs libevent's locking, enabled before any
  // event_base exists.
  std::call_once(g_threads_once, [] {
    if (evthread_use_pthreads() != 0) throw HttpServerError("evthread_use_pthreads failed");
  });
  // A client that goes away mid-write must not kill the service: libevent writes with
  // writev(), which raises SIGPIPE. Every socket server ignores it; do so unless the
  // program has its own handler.
  struct sigaction old {};
  if (sigaction(SIGPIPE, nullptr, &old) == 0 && old.sa_handler == SIG_DFL) {
    std::signal(SIGPIPE, SIG_IGN);
  }

  int fd = config.listen_fd;
  if (fd >= 0) {
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
  } else {
    fd = open_listener(config.address, config.port);
  }
  port = bound_port(fd);

  base = event_base_new();
  http = base ? evhttp_new(base) : nullptr;
  evhttp_bound_socket* bound = http ? evhttp_accept_socket_with_handle(http, fd) : nullptr;
  if (bound == nullptr) {
    close(fd);
    throw HttpServerError("HTTP: cannot set up libevent");
  }
  listener = evhttp_bound_socket_get_listener(bound);
  {
    std::lock_guard lock(g_listeners_mutex);
    g_listeners[listener] = this;
  }
  evconnlistener_set_error_cb(listener, on_accept_error_cb);
  evhttp_set_allowed_methods(http, EVHTTP_REQ_GET | EVHTTP_REQ_POST | EVHTTP_REQ_HEAD |
                                       EVHTTP_REQ_PUT | EVHTTP_REQ_DELETE | EVHTTP_REQ_OPTIONS |
                                       EVHTTP_REQ_TRACE | EVHTTP_REQ_CONNECT | EVHTTP_REQ_PATCH);
  evhttp_set_timeout(http, static_cast<int>(config.request_timeout.count()));
  evhttp_set_max_headers_size(http, ev_ssize_t{16} * 1024);
  // Only a WHEP offer has a body: a larger Content-Length gets 413 before it is read.
  evhttp_set_max_body_size(http, static_cast<ev_ssize_t>(kMaxWhepOfferBytes));
  evhttp_set_gencb(http, on_request_cb, this);
  connections = std::make_unique<HttpConnections>(
      base, http,
      HttpConnectionLimits{.max_connections = config.max_connections,
                           .header_timeout = config.header_timeout},
      [this] { drop_slow_streams(); });

  frame_event = event_new(base, -1, 0, on_frame_cb, this);
  stop_event = event_new(base, -1, 0, on_stop_cb, this);
  resume_accept_event = evtimer_new(base, on_resume_accept_cb, this);
  whep_event = event_new(base, -1, 0, on_whep_done_cb, this);
  {
    std::lock_guard lock(whep_mailbox->mutex);
    whep_mailbox->wake = whep_event;
  }
  if (frame_event == nullptr || stop_event == nullptr || resume_accept_event == nullptr ||
      whep_event == nullptr) {
    throw HttpServerError("HTTP: cannot create events");
  }
}

void HttpServer::Impl::teardown() {
  // The loop has stopped: nothing runs on the server thread any more. Connections are
  // freed by evhttp_free() with the requests they own; a stream whose connection already
  // failed had its request handed back to us and is freed here.
  for (auto& client : clients) {
    if (client->request == nullptr) continue;
    if (evhttp_connection* conn = evhttp_request_get_connection(client->request)) {
      evhttp_connection_set_closecb(conn, nullptr, nullptr);
      evhttp_request_set_on_complete_cb(client->request, nullptr, nullptr);
    } else {
      evhttp_request_free(client->request);
    }
  }
  {
    std::lock_guard lock(stats_mutex);
    clients.clear();
  }
  if (listener) {
    std::lock_guard lock(g_listeners_mutex);
    g_listeners.erase(listener);
  }
  drop_pending_whep();
  if (http) evhttp_free(http);
  connections.reset();  // after evhttp's connections, before the base
  if (frame_event) event_free(frame_event);
  if (stop_event) event_free(stop_event);
  if (resume_accept_event) event_free(resume_accept_event);
  if (whep_event) event_free(whep_event);
  if (base) event_base_free(base);
  http = nullptr;
  listener = nullptr;
  frame_event = stop_event = resume_accept_event = whep_event = nullptr;
  base = nullptr;
}

void HttpServer::Impl::add_common_headers(evkeyvalq* headers, const char* content_type) {
  evhttp_add_header(headers, "Content-Type", content_type);
  evhttp_add_header(headers, "Cache-Control", kNoCache);
  if (!config.access.cors_origin.empty())
    evhttp_add_header(headers, "Access-Control-Allow-Origin", config.access.cors_origin.c_str());
}

void HttpServer::Impl::send_body(evhttp_request* req, int code, const char* reason,
                                 const char* content_type, evbuffer* body) {
  evkeyvalq* headers = evhttp_request_get_output_headers(req);
  add_common_headers(headers, content_type);
  if (evhttp_request_get_command(req) == EVHTTP_REQ_HEAD) {
    // The headers a GET would get, Content-Length included, and no body (RFC 9110 9.3.2).
    evhttp_add_header(headers, "Content-Length", std::to_string(evbuffer_get_length(body)).c_str());
    evbuffer_drain(body, evbuffer_get_length(body));
  }
  {
    std::lock_guard lock(stats_mutex);
    bytes_queued += evbuffer_get_length(body);
  }
  evhttp_send_reply(req, code, reason, body);
}

void HttpServer::Impl::send_text(evhttp_request* req, int code, const char* reason,
                                 const std::string& text) {
  evbuffer* body = evbuffer_new();
  evbuffer_add(body, text.data(), text.size());
  send_body(req, code, reason, "text/plain; charset=utf-8", body);
  evbuffer_free(body);
}

void HttpServer::Impl::on_request(evhttp_request* req) {
  {
    std::lock_guard lock(stats_mutex);
    ++requests;
  }
  const evhttp_uri* uri = evhttp_request_get_evhttp_uri(req);
  const char* path = uri ? evhttp_uri_get_path(uri) : nullptr;
  const char* query = uri ? evhttp_uri_get_query(uri) : nullptr;
  const std::string_view p = path && *path ? path : "/";
  if (evhttp_connection* conn = evhttp_request_get_connection(req))
    connections->request_arrived(evhttp_connection_get_bufferevent(conn));
  if (!admit(req)) return;
  const Route route = route_for(p, query);
  if (route == Route::NotFound) {
    send_text(req, HTTP_NOTFOUND, "Not Found", "not found: " + std::string(p) + "\n");
    return;
  }
  if (route == Route::Whep || route == Route::WhepResource) {
    serve_whep(req, route == Route::WhepResource, p);
    return;
  }
  const evhttp_cmd_type method = evhttp_request_get_command(req);
  if (method == EVHTTP_REQ_OPTIONS) {
    serve_options(req);
    return;
  }
  if (method != EVHTTP_REQ_GET && method != EVHTTP_REQ_HEAD) {
    evhttp_add_header(evhttp_request_get_output_headers(req), "Allow", kAllowed);
    send_text(req, 405, "Method Not Allowed", "only GET, HEAD and OPTIONS are served here\n");
    return;
  }
  switch (route) {
    case Route::Stream:
      serve_stream(req);
      return;
    case Route::Snapshot:
      serve_snapshot(req);
      return;
    case Route::Status:
      serve_status(req);
      return;
    case Route::State:
      serve_state(req);
      return;
    case Route::Metrics:
      serve_metrics(req);
      return;
    case Route::Index: {
      evbuffer* body = evbuffer_new();
      const std::string_view page = viewer_html();
      evbuffer_add_reference(body, page.data(), page.size(), nullptr, nullptr);
      send_body(req, HTTP_OK, "OK", "text/html; charset=utf-8", body);
      evbuffer_free(body);
      return;
    }
    case Route::Whep:
    case Route::WhepResource:
    case Route::NotFound:
      return;
  }
}

// The access rules of http_access.hpp. False: answered here.
bool HttpServer::Impl::admit(evhttp_request* req) {
  evkeyvalq* in = evhttp_request_get_input_headers(req);
  const AccessDecision decision =
      check_access(config.access, config.address, evhttp_find_header(in, "Host"),
                   evhttp_find_header(in, "Authorization"));
  // A CORS preflight carries no credentials (Fetch standard) and an OPTIONS answer tells
  // only what is allowed, so OPTIONS needs the Host check alone.
  const bool options = evhttp_request_get_command(req) == EVHTTP_REQ_OPTIONS;
  if (decision == AccessDecision::Allow || (options && decision != AccessDecision::BadHost))
    return true;
  {
    std::lock_guard lock(stats_mutex);
    ++refused;
  }
  if (decision == AccessDecision::BadHost) {
    send_text(req, 403, "Forbidden", "this server does not answer to that Host\n");
  } else {
    evhttp_add_header(evhttp_request_get_output_headers(req), "WWW-Authenticate",
                      authenticate_challenge(config.access).c_str());
    send_text(req, 401, "Unauthorized", "authentication required\n");
  }
  return false;
}

void HttpServer::Impl::on_accept_error() {
  {
    std::lock_guard lock(stats_mutex);
    ++accept_failures;
  }
  // Out of descriptors (or memory): the pending connection stays in the backlog and the
  // listening socket stays readable, so retrying now would only spin. Pause, then retry.
  evconnlistener_disable(listener);
  const auto ms = config.accept_backoff.count();
  const timeval pause{static_cast<time_t>(ms / 1000), static_cast<suseconds_t>(ms % 1000 * 1000)};
  evtimer_add(resume_accept_event, &pause);
}

void HttpServer::Impl::serve_stream(evhttp_request* req) {
  evhttp_connection* conn = evhttp_request_get_connection(req);
  if (conn == nullptr) return;
  if (evhttp_request_get_command(req) == EVHTTP_REQ_HEAD) {
    // The stream's headers and no part: nothing is registered, no slot is taken, and no
    // Content-Length (a stream has none).
    add_common_headers(evhttp_request_get_output_headers(req),
                       (std::string("multipart/x-mixed-replace;boundary=") + kBoundary).c_str());
    evhttp_send_reply(req, HTTP_OK, "OK", nullptr);
    return;
  }
  if (clients.size() >= static_cast<std::size_t>(config.max_stream_clients)) {
    evhttp_add_header(evhttp_request_get_output_headers(req), "Retry-After", "5");
    send_text(req, 503, "Service Unavailable", "too many stream clients\n");
    return;
  }
  char* address = nullptr;
  ev_uint16_t port_number = 0;
  evhttp_connection_get_peer(conn, &address, &port_number);
  const std::string peer_address = address ? address : "?";
  const auto same_peer = std::count_if(clients.begin(), clients.end(), [&](const auto& c) {
    return c->request != nullptr && c->peer_address == peer_address;
  });
  // Loopback peers are exempt: on the box itself every local client (a recorder, a reverse
  // proxy) shares one address, and a local process could open the sockets anyway.
  if (!is_loopback_address(peer_address) && config.access.max_streams_per_peer > 0 &&
      same_peer >= config.access.max_streams_per_peer) {
    evhttp_add_header(evhttp_request_get_output_headers(req), "Retry-After", "5");
    send_text(req, 429, "Too Many Requests", "too many streams from this address\n");
    return;
  }
  evkeyvalq* headers = evhttp_request_get_output_headers(req);
  evhttp_add_header(headers, "Content-Type",
                    (std::string("multipart/x-mixed-replace;boundary=") + kBoundary).c_str());
  if (!config.access.cors_origin.empty())
    evhttp_add_header(headers, "Access-Control-Allow-Origin", config.access.cors_origin.c_str());
  evhttp_add_header(headers, "Cache-Control", kNoCache);
  evhttp_add_header(headers, "Pragma", "no-cache");
  evhttp_add_header(headers, "Expires", "Mon, 3 Jan 2000 12:34:56 GMT");
  // HTTP/1.1 clients get chunked transfer; HTTP/1.0 clients the raw multipart body.
  evhttp_send_reply_start(req, HTTP_OK, "OK");

  auto client = std::make_unique<StreamClient>();
  client->server = this;
  client->request = req;
  client->connected_ns = monotonic_now_ns();
  client->peer_address = peer_address;
  client->peer = peer_address + ":" + std::to_string(port_number);
  const evhttp_uri* uri = evhttp_request_get_evhttp_uri(req);
  client->options = parse_stream_options(uri ? evhttp_uri_get_query(uri) : nullptr);
  char id[24];
  std::snprintf(id, sizeof id, "%llx", static_cast<unsigned long long>(++next_client_id));
  client->id = id;

  // A stream never reads again, so no read timeout; a write timeout drops a dead client.
  bufferevent* bev = evhttp_connection_get_bufferevent(conn);
  const timeval stall{static_cast<time_t>(config.stalled_client_timeout.count()), 0};
  bufferevent_set_timeouts(bev, nullptr,
                           config.stalled_client_timeout.count() > 0 ? &stall : nullptr);
  bufferevent_setwatermark(bev, EV_READ, 0, kStreamInputLimit);
  connections->became_stream(bev);
  evhttp_connection_set_closecb(conn, on_stream_closed_cb, client.get());
  evhttp_request_set_on_complete_cb(req, on_stream_complete_cb, client.get());

  StreamClient& ref = *client;
  {
    std::lock_guard lock(stats_mutex);
    clients.push_back(std::move(client));
  }
  offer(ref);  // the newest frame at once, not at the next publish
}

void HttpServer::Impl::offer(StreamClient& client) {
  if (client.request == nullptr) return;
  if (!current) {
    // ustreamer streams its blank frame until the source sends one: a viewer that connects
    // before the first frame sees NO SIGNAL (X-UStreamer-Online: false), not a hung request.
    if (client.frames_sent > 0 || !make_placeholder()) return;
    const TimestampNs now = monotonic_now_ns();
    send_part(client, placeholder,
              {.length = placeholder->size(),
               .capture_ns = now,
               .capture_wall_ns = wall_clock_ns(now),
               .online = false,
               .size = shown_size()},
              0);
    return;
  }
  if (client.last_sent >= current->sequence) return;
  const EncodedFrame& frame = current->value;
  send_part(client, frame.jpeg,
            {.length = frame.jpeg->size(),
             .capture_ns = frame.timestamp_ns,
             .capture_wall_ns = current_wall_ns,
             .online = !frame.no_signal,
             .size = current_size},
            current->sequence);
}

void HttpServer::Impl::send_part(StreamClient& client,
                                 const std::shared_ptr<const std::vector<std::uint8_t>>& jpeg,
                                 const PartFrame& frame, std::uint64_t sequence) {
  evhttp_connection* conn = evhttp_request_get_connection(client.request);
  if (conn == nullptr) return;  // failed; its close callback removes it
  bufferevent* bev = evhttp_connection_get_bufferevent(conn);
  const std::size_t buffered = evbuffer_get_length(bufferevent_get_output(bev));
  if (buffered > config.client_buffer_limit) {
    std::lock_guard lock(stats_mutex);
    client.buffered = buffered;
    return;  // skipped for now; the drain callback offers the newest frame again
  }

  const TimestampNs now = monotonic_now_ns();
  evbuffer* part = evbuffer_new();
  std::string head;
  if (!client.options.advance_headers) {
    head = stream_part_head(frame, client.options.extra_headers, client.sent_rate.rate_hz(now));
  } else if (client.frames_sent == 0) {
    head = advance_part_head();  // later parts' heads went out after the frame before
  }
  evbuffer_add(part, head.data(), head.size());
  add_jpeg_reference(part, jpeg);
  evbuffer_add(part, "\r\n", 2);
  if (client.options.advance_headers) {
    const std::string next = advance_part_head();
    evbuffer_add(part, next.data(), next.size());
  }
  const std::size_t part_bytes = evbuffer_get_length(part);
  evhttp_send_reply_chunk_with_cb(client.request, part, on_stream_drained_cb, &client);
  evbuffer_free(part);
  // evhttp adds the part and its chunk framing to the output buffer at once; the socket is
  // written later, from the loop, so the difference is what this part added.
  const std::size_t after = evbuffer_get_length(bufferevent_get_output(bev));
  std::lock_guard lock(stats_mutex);
  if (client.last_sent > 0 && sequence > 0) client.skipped += sequence - client.last_sent - 1;
  client.last_sent = sequence;
  ++client.frames_sent;
  client.sent_rate.tick(now);
  client.bytes_added += after > buffered ? after - buffered : part_bytes;
  client.queued_parts.emplace_back(client.bytes_added, monotonic_now_ns());
  client.buffered = after;
  bytes_queued += part_bytes;
}

void HttpServer::Impl::drained(StreamClient& client) {
  {
    std::lock_guard lock(stats_mutex);
    client.buffered = 0;
  }
  offer(client);
}

// Every sweep: a stream client whose oldest frame not yet handed whole to the kernel was
// queued more than stalled_client_timeout ago is dropped, however many bytes it takes now and
// then. The kernel's send queue is not counted: it is bounded by the socket's send buffer,
// and on loopback it grows to megabytes (2.7 MB measured), which would put any reader slower
// than the stream, one the buffer limit already serves by skipping frames, seconds behind. A
// client is dropped once at most client_buffer_limit + one frame, queued behind the full
// kernel queue, takes it longer than the timeout: a reader slower than about
// (client_buffer_limit + a frame) / stalled_client_timeout.
void HttpServer::Impl::drop_slow_streams() {
  const TimestampNs now = monotonic_now_ns();
  const TimestampNs limit_ns = ms_to_ns(
      std::chrono::duration_cast<std::chrono::milliseconds>(config.stalled_client_timeout).count());
  std::vector<evhttp_connection*> slow;
  for (auto& client : clients) {
    if (client->request == nullptr) continue;
    evhttp_connection* conn = evhttp_request_get_connection(client->request);
    if (conn == nullptr) continue;
    bufferevent* bev = evhttp_connection_get_bufferevent(conn);
    const std::size_t left = evbuffer_get_length(bufferevent_get_output(bev));
    auto& parts = client->queued_parts;
    while (!parts.empty() && client->bytes_added - parts.front().first >= left) parts.pop_front();
    if (limit_ns > 0 && !parts.empty() && now - parts.front().second > limit_ns) {
      // Reset, not closed: a close would queue the FIN behind the kernel's send queue, which
      // the reader would still get at its trickle (minutes for megabytes) before seeing the
      // end, while the orphaned socket kept that memory. With a zero linger the close
      // (evhttp's, or our connection tracker's) discards the queue and sends a reset.
      const linger abort{1, 0};
      setsockopt(bufferevent_getfd(bev), SOL_SOCKET, SO_LINGER, &abort, sizeof abort);
      slow.push_back(conn);
    }
  }
  // Freeing a connection runs its close callback, which removes the client from the list;
  // the tracker closes the socket right after this returns (HttpConnections::sweep).
  for (evhttp_connection* conn : slow) evhttp_connection_free(conn);
  std::lock_guard lock(stats_mutex);
  slow_streams_dropped += slow.size();
  connection_counts = connections->counts();
}

void HttpServer::Impl::on_frame() {
  const auto after = current ? current->sequence : 0;
  auto item = frames.try_newer(after);
  if (!item) return;
  current = std::move(item);
  current_size = jpeg_size(*current->value.jpeg).value_or(JpegSize{});
  current_wall_ns = wall_clock_ns(current->value.timestamp_ns);
  for (auto& client : clients) offer(*client);
}

void HttpServer::Impl::remove(StreamClient* client) {
  // The connection is being freed. A request that failed mid-stream was detached from it
  // and is ours to free; one still attached is freed by libevent right after this.
  if (client->request != nullptr && evhttp_request_get_connection(client->request) == nullptr) {
    evhttp_request_free(client->request);
  }
  std::lock_guard lock(stats_mutex);
  bytes_dropped += client->buffered;
  clients.remove_if([&](const auto& c) { return c.get() == client; });
}

HttpServerStats HttpServer::Impl::stats() const {
  HttpServerStats s;
  s.frames_published = frames.sequence();
  const auto latest = s.frames_published;
  const TimestampNs now = monotonic_now_ns();
  std::lock_guard lock(stats_mutex);
  s.requests = requests;
  s.refused = refused;
  s.accept_failures = accept_failures;
  s.connections = connection_counts.open;
  s.header_timeouts = connection_counts.header_timeouts;
  s.evicted = connection_counts.evicted;
  s.slow_streams_dropped = slow_streams_dropped;
  std::uint64_t unsent = bytes_dropped;
  for (const auto& c : clients) {
    StreamClientStats cs;
    cs.peer = c->peer;
    cs.frames_sent = c->frames_sent;
    // Frames between the last one sent and the newest are lost to this client for good.
    cs.drops = c->skipped +
               (c->last_sent > 0 && latest > c->last_sent + 1 ? latest - c->last_sent - 1 : 0);
    cs.buffered_bytes = c->buffered;
    cs.connected_s = static_cast<double>(now - c->connected_ns) * 1e-9;
    unsent += c->buffered;
    s.stream_clients.push_back(std::move(cs));
  }
  s.bytes_sent = bytes_queued > unsent ? bytes_queued - unsent : 0;
  return s;
}

nlohmann::json to_json(const HttpServerStats& stats) {
  nlohmann::json clients = nlohmann::json::array();
  for (const auto& c : stats.stream_clients) {
    clients.push_back({{"peer", c.peer},
                       {"frames_sent", c.frames_sent},
                       {"drops", c.drops},
                       {"buffered_bytes", c.buffered_bytes},
                       {"connected_s", c.connected_s}});
  }
  return {{"requests", stats.requests},
          {"refused", stats.refused},
          {"accept_failures", stats.accept_failures},
          {"connections", stats.connections},
          {"header_timeouts", stats.header_timeouts},
          {"evicted", stats.evicted},
          {"slow_streams_dropped", stats.slow_streams_dropped},
          {"frames_published", stats.frames_published},
          {"bytes_sent", stats.bytes_sent},
          {"clients", stats.stream_clients.size()},
          {"stream_clients", std::move(clients)}};
}

HttpServer::HttpServer(HttpServerConfig config, StatusCallback status)
    : impl_(std::make_unique<Impl>()), jpeg_quality_(config.jpeg_quality) {
  impl_->config = std::move(config);
  impl_->status = std::move(status);
  try {
    impl_->setup();
  } catch (...) {
    impl_->teardown();
    throw;
  }
  impl_->running = true;
  impl_->thread =
      std::thread([impl = impl_.get()] { event_base_loop(impl->base, EVLOOP_NO_EXIT_ON_EMPTY); });
}

HttpServer::~HttpServer() {
  stop();
}

int HttpServer::port() const {
  return impl_->port;
}

std::string HttpServer::url() const {
  const std::string& a = impl_->config.address;
  const std::string host = a.find(':') != std::string::npos ? "[" + a + "]" : a;
  return "http://" + host + ":" + std::to_string(impl_->port);
}

void HttpServer::publish(EncodedFrame frame) {
  if (!frame.jpeg || frame.jpeg->empty()) return;
  impl_->published_rate.tick(monotonic_now_ns());
  impl_->frames.publish(std::move(frame));
  std::lock_guard lock(impl_->wake_mutex);
  if (impl_->running) event_active(impl_->frame_event, EV_READ, 0);
}

void HttpServer::stop() {
  {
    std::lock_guard lock(impl_->wake_mutex);
    if (!impl_->running) return;
    impl_->running = false;
    // An activated event stays active until the loop runs it, so this cannot be lost even
    // if the loop has not started yet (event_base_loopbreak() before the loop would be).
    event_active(impl_->stop_event, EV_READ, 0);
  }
  if (impl_->thread.joinable()) impl_->thread.join();
  impl_->teardown();
  impl_->heartbeat = {};  // stopped on purpose: no longer watched
}

namespace {

constexpr timeval kHeartbeatEvery{0, 250'000};

// A one-shot timer that re-arms itself: libevent frees one-shot events with the base, so
// teardown() needs no part in it.
void on_heartbeat_cb(evutil_socket_t, short, void* arg) {
  auto* impl = static_cast<HttpServer::Impl*>(arg);
  impl->heartbeat.beat();
  event_base_once(impl->base, -1, EV_TIMEOUT, on_heartbeat_cb, impl, &kHeartbeatEvery);
}

}  // namespace

void HttpServer::watch(HeartbeatRegistry& heartbeats) {
  std::lock_guard lock(impl_->wake_mutex);
  if (!impl_->running) return;
  impl_->heartbeat = heartbeats.add("http");
  event_base_once(impl_->base, -1, EV_TIMEOUT, on_heartbeat_cb, impl_.get(), &kHeartbeatEvery);
}

HttpServerStats HttpServer::stats() const {
  return impl_->stats();
}

}  // namespace probeless
