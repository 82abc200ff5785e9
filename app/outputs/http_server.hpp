#pragma once
// The network side of the appliance: an HTTP server on its own thread (libevent's evhttp,
// its own event_base) serving the latest encoded frame the ways existing MJPEG clients
// expect (mjpg-streamer and ustreamer URLs and headers):
//
//   GET /stream    (also /?action=stream)    multipart/x-mixed-replace MJPEG
//   GET /snapshot  (also /?action=snapshot)  one JPEG; a NO SIGNAL one before the first frame
//   GET /status    JSON: the service's status callback plus this server's counters
//   GET /state     ustreamer's JSON (app/outputs/http_compat.hpp)
//   GET /metrics   /status in Prometheus' text format (app/outputs/http_metrics.hpp)
//   GET /          a self-contained viewer page (WebRTC or the stream, the status table)
//   POST /whep     WHEP: an SDP offer in, the answer out (also /<path>/whep; DELETE ends it)
//
// HEAD answers any of them without the body, OPTIONS with what is allowed (ustreamer's).
//
// Frames arrive already encoded (once, whatever the number of clients) through publish()
// (or offer(), as an Output of the pipeline, app/outputs/output.hpp), which never blocks: it
// replaces the value in a LatestFrame slot and wakes the server's thread. Every stream client gets
// the newest frame; one whose socket does not keep up has frames skipped (counted as its drops)
// instead of slowing the pipeline or other clients. docs/outputs.md has the details.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/outputs/http_access.hpp"
#include "app/outputs/output.hpp"
#include "app/outputs/whep_endpoint.hpp"
#include "core/time.hpp"

namespace probeless {

struct EncodedFrame {
  std::shared_ptr<const std::vector<std::uint8_t>> jpeg;
  TimestampNs timestamp_ns = 0;  // the frame's capture time (CLOCK_MONOTONIC)
  bool no_signal = false;        // the NO SIGNAL banner over the last good frame
};

// [http] of the service config (docs/configuration.md).
struct HttpServerConfig {
  bool enabled = true;                // the service's; the server itself ignores it
  std::string address = "127.0.0.1";  // IPv4 or IPv6 literal; "0.0.0.0" opens to the network
  int port = 8080;                    // 0: an ephemeral port (tests), see HttpServer::port()
  // An already listening socket to serve instead of binding (systemd socket activation:
  // SD_LISTEN_FDS_START); address and port are then ignored. The server takes ownership.
  int listen_fd = -1;
  // A stream client with more than this many bytes still queued for it gets no new frame
  // until it catches up: about five 640x480 frames at quality 80 (~45 KB each), bounding
  // both memory per client and how stale a slow client's picture can get.
  std::size_t client_buffer_limit = std::size_t{256} * 1024;
  // A stream client is disconnected when a frame queued for it has not been taken whole this
  // long after it was queued: one that stops reading, and one that reads a trickle (a byte
  // now and then used to reset the timer forever), about 10 KB/s or less with the defaults
  // (the queue of a client at the buffer limit is ~300 KB). Its slot is then free.
  std::chrono::seconds stalled_client_timeout{30};
  // Requests other than streams time out after this much inactivity.
  std::chrono::seconds request_timeout{30};
  // Open connections at most (streams included); past it the oldest connections still
  // waiting for their request's headers are closed to make room, so a flood of idle or
  // slow connections cannot keep a new viewer out. 512 keeps the server within half of
  // systemd's default LimitNOFILE soft limit (1024), beside the ~100 descriptors the service
  // holds itself, and ~16 KB of header buffer each (8 MB at most). docs/security.md "Limits".
  int max_connections = 512;
  // A request's headers must all arrive within this of the connection's accept (or of the
  // end of the previous response on a keep-alive connection), however steadily they trickle
  // in: the slowloris bound. A browser sends them in one packet.
  std::chrono::milliseconds header_timeout{10000};
  int max_stream_clients = 32;  // more get 503: an SBC's uplink is the limit long before
  int jpeg_quality = 80;        // of the frames the pipeline encodes for this server
  HttpAccessConfig access;      // Host check, authentication, CORS (app/outputs/http_access.hpp)
  // When accept() fails for want of descriptors (EMFILE/ENFILE), the listener pauses this
  // long instead of retrying at once: libevent 2.1 would otherwise spin on the pending
  // connection and log every attempt.
  std::chrono::milliseconds accept_backoff{250};
};

struct StreamClientStats {
  std::string peer;  // "address:port"
  std::uint64_t frames_sent = 0;
  std::uint64_t drops = 0;  // frames published while connected that this client will not get
  std::size_t buffered_bytes = 0;
  double connected_s = 0;
};

struct HttpServerStats {
  std::uint64_t requests = 0;
  std::uint64_t refused = 0;          // failed the Host check or authentication
  std::uint64_t accept_failures = 0;  // accept() errors (out of descriptors), each a pause
  std::size_t connections = 0;        // open now, streams included
  std::uint64_t header_timeouts = 0;  // closed: headers not complete within header_timeout
  std::uint64_t evicted = 0;          // closed waiting for headers to stay within max_connections
  std::uint64_t slow_streams_dropped = 0;  // stream clients cut by stalled_client_timeout
  std::uint64_t frames_published = 0;
  std::uint64_t bytes_sent = 0;  // handed to the kernel, all responses
  std::vector<StreamClientStats> stream_clients;
};

nlohmann::json to_json(const HttpServerStats& stats);

struct HttpServerError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class HttpServer final : public Output {
 public:
  // Called on the server's thread for every GET /status; must be thread-safe with respect
  // to the pipeline. An object is served with this server's stats added under "http".
  using StatusCallback = std::function<nlohmann::json()>;

  // Binds and starts serving; throws HttpServerError naming the address when it cannot.
  explicit HttpServer(HttpServerConfig config, StatusCallback status = {});
  ~HttpServer() override;
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;
  HttpServer(HttpServer&&) = delete;
  HttpServer& operator=(HttpServer&&) = delete;

  int port() const;                  // the bound port (the ephemeral one when configured with 0)
  std::string url() const override;  // "http://127.0.0.1:8080"

  // Any thread, never blocks on clients. Frames without data are ignored.
  void publish(EncodedFrame frame);

  // Closes every connection and joins the thread (well under a second). Idempotent.
  void stop() override;

  // Output: the JPEG at the configured quality, published as it comes.
  std::string_view name() const override { return "http"; }
  OutputNeeds needs() const override { return {.jpeg = true, .jpeg_quality = jpeg_quality_}; }
  void offer(const OutputFrame& frame) override {
    publish({frame.jpeg, frame.timestamp_ns, frame.no_signal});
  }

  HttpServerStats stats() const;

  // Where POST /whep offers go (the WebRTC output); null: /whep answers 404. Any thread.
  void set_whep(std::shared_ptr<WhepEndpoint> endpoint);

  // The event loop beats "http" every 250 ms from a timer of its own (issue #20 item 6).
  void watch(HeartbeatRegistry& heartbeats) override;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  int jpeg_quality_;
};

}  // namespace probeless
