#pragma once
// Every connection the HTTP server has accepted, from accept to close, for the limits
// libevent 2.1's evhttp lacks (issue #20): a cap on open connections and a total deadline for
// a request's headers. evhttp's own timeout is one of inactivity, which a slowloris (a byte
// every few seconds) resets forever, and it accepts until the process runs out of descriptors.
//
// evhttp creates each connection's bufferevent through our callback (evhttp_set_bevcb), so
// every accepted connection passes here. We hold a reference on the bufferevent: evhttp's
// bufferevent_free() then only clears its callbacks, which a periodic sweep notices (the error
// callback is set for as long as evhttp owns the connection), and the sweep drops our
// reference, which closes the socket. The evhttp_connection is the callbacks' argument, so a
// connection past its deadline, or the oldest waiting one over the cap, is freed the way
// evhttp frees its own (evhttp_connection_free: no reply, its requests freed with it).
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <unordered_map>

#include "core/time.hpp"

struct bufferevent;
struct event;
struct event_base;
struct evhttp;

namespace probeless {

struct HttpConnectionLimits {
  int max_connections = 512;
  std::chrono::milliseconds header_timeout{10000};
  std::chrono::milliseconds sweep_period{250};  // how late a deadline may be enforced
};

struct HttpConnectionCounts {
  std::size_t open = 0;
  std::uint64_t accepted = 0;
  std::uint64_t header_timeouts = 0;  // closed: headers not complete in header_timeout
  std::uint64_t evicted = 0;          // closed to make room over max_connections
};

class HttpConnections {
 public:
  // Installs the bufferevent callback on `http` and a sweep timer on `base`; `on_sweep` runs
  // after each sweep, on the server's thread (the stream clients' own checks).
  HttpConnections(event_base* base, evhttp* http, HttpConnectionLimits limits,
                  std::function<void()> on_sweep);
  // After evhttp_free() (which frees every connection) and before event_base_free().
  ~HttpConnections();
  HttpConnections(const HttpConnections&) = delete;
  HttpConnections& operator=(const HttpConnections&) = delete;

  // A request's headers (and body) arrived on this connection: not waiting any more.
  void request_arrived(bufferevent* bev);
  // The connection now carries a stream: its deadlines are the stream client's own.
  void became_stream(bufferevent* bev);

  HttpConnectionCounts counts() const { return counts_; }  // the server's thread only

  bufferevent* on_new_connection();
  void sweep();

 private:
  struct Tracked {
    TimestampNs waiting_since = 0;  // for a request's headers; 0 while one is served
    bool stream = false;
  };
  void release_closed();
  void close(bufferevent* bev);

  event_base* base_;
  HttpConnectionLimits limits_;
  std::function<void()> on_sweep_;
  event* sweep_event_ = nullptr;
  std::unordered_map<bufferevent*, Tracked> tracked_;
  HttpConnectionCounts counts_;
};

}  // namespace probeless
