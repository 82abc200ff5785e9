#pragma once
// The clients of `probeless bench http` (issue #20 item 3), all over loopback on one epoll
// loop of their own thread: viewers that take every byte of /stream, stalled viewers that ask
// for /stream and never read, idle connections that never send a request, and a slowloris
// that sends a request's headers one byte every couple of seconds. Idle and slowloris
// connections the server closes are opened again at once, so the attack keeps its size.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <thread>

namespace probeless::lab {

struct HttpLoadMix {
  int viewers = 64;
  int stalled = 8;
  int idle = 200;
  int slowloris = 200;
  std::chrono::milliseconds slowloris_byte_period{2000};
};

struct HttpLoadCounts {
  std::uint64_t viewer_bytes = 0;
  std::uint64_t reconnects = 0;      // idle and slowloris connections reopened after a close
  std::uint64_t viewers_closed = 0;  // viewers whose stream ended (refused or dropped)
};

class HttpLoad {
 public:
  HttpLoad(int port, HttpLoadMix mix);  // connects everything, then runs until destroyed
  ~HttpLoad();                          // closes every connection
  HttpLoad(const HttpLoad&) = delete;
  HttpLoad& operator=(const HttpLoad&) = delete;
  HttpLoadCounts counts() const;

 private:
  void run(std::stop_token stop);
  int port_;
  HttpLoadMix mix_;
  std::atomic<std::uint64_t> viewer_bytes_{0}, reconnects_{0}, viewers_closed_{0};
  std::jthread thread_;
};

// Milliseconds from connect to the end of the first JPEG part of /stream (a new viewer's
// wait for its first picture); none when it does not come within `timeout`.
std::optional<double> time_to_first_frame(int port, std::chrono::milliseconds timeout);

// A viewer that leaves mid-frame: GET /stream, read `bytes` of the response (its head and the
// start of a JPEG), then close with a reset (SO_LINGER 0). Runs `count` of them, `batch` at a
// time; returns how many got their bytes before leaving.
int viewers_leaving_mid_frame(int port, int count, int batch = 50, std::size_t bytes = 2000);

// Raises this process's soft descriptor limit to its hard limit; returns the new soft limit.
long raise_descriptor_limit();

}  // namespace probeless::lab
