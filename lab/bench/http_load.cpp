#include "lab/bench/http_load.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace probeless::lab {
namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kStreamRequest = "GET /stream HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
constexpr const char* kSlowRequest =
    "GET /status HTTP/1.1\r\nHost: 127.0.0.1\r\nUser-Agent: slowloris\r\nX-a: ";

// A connected loopback socket (blocking connect, then non-blocking), -1 on failure.
int connect_to(int port, int receive_buffer = 0) {
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  if (receive_buffer > 0)
    setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return -1;
  }
  fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
  return fd;
}

void send_text(int fd, const char* text) {
  send(fd, text, std::strlen(text), MSG_NOSIGNAL);
}

void reset_and_close(int fd) {
  const linger reset{1, 0};
  setsockopt(fd, SOL_SOCKET, SO_LINGER, &reset, sizeof reset);
  close(fd);
}

enum class Kind { Viewer, Stalled, Idle, Slowloris };

}  // namespace

HttpLoad::HttpLoad(int port, HttpLoadMix mix)
    : port_(port), mix_(mix), thread_([this](std::stop_token stop) { run(stop); }) {}

HttpLoad::~HttpLoad() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

HttpLoadCounts HttpLoad::counts() const {
  return {viewer_bytes_.load(), reconnects_.load(), viewers_closed_.load()};
}

void HttpLoad::run(std::stop_token stop) {
  const int ep = epoll_create1(EPOLL_CLOEXEC);
  std::unordered_map<int, Kind> kinds;
  auto open_one = [&](Kind kind) {
    const int fd = connect_to(port_, kind == Kind::Stalled ? 4096 : 0);
    if (fd < 0) return;
    if (kind == Kind::Viewer || kind == Kind::Stalled) send_text(fd, kStreamRequest);
    if (kind == Kind::Slowloris) send_text(fd, kSlowRequest);
    kinds[fd] = kind;
    // Stalled viewers are watched for their close only (never read).
    epoll_event e{};
    e.events = kind == Kind::Stalled ? EPOLLRDHUP : EPOLLIN | EPOLLRDHUP;
    e.data.fd = fd;
    epoll_ctl(ep, EPOLL_CTL_ADD, fd, &e);
  };
  for (int i = 0; i < mix_.viewers; ++i) open_one(Kind::Viewer);
  for (int i = 0; i < mix_.stalled; ++i) open_one(Kind::Stalled);
  for (int i = 0; i < mix_.idle; ++i) open_one(Kind::Idle);
  for (int i = 0; i < mix_.slowloris; ++i) open_one(Kind::Slowloris);

  auto next_byte = Clock::now() + mix_.slowloris_byte_period;
  std::vector<epoll_event> events(256);
  std::vector<char> buf(1 << 16);
  while (!stop.stop_requested()) {
    const int n = epoll_wait(ep, events.data(), static_cast<int>(events.size()), 50);
    for (int i = 0; i < n; ++i) {
      const int fd = events[i].data.fd;
      const Kind kind = kinds[fd];
      bool closed = (events[i].events & (EPOLLRDHUP | EPOLLHUP | EPOLLERR)) != 0;
      if (!closed && (events[i].events & EPOLLIN)) {
        for (;;) {
          const ssize_t got = recv(fd, buf.data(), buf.size(), 0);
          if (got > 0) {
            if (kind == Kind::Viewer) viewer_bytes_ += static_cast<std::uint64_t>(got);
            continue;
          }
          closed = got == 0 || (errno != EAGAIN && errno != EWOULDBLOCK);
          break;
        }
      }
      if (!closed) continue;
      epoll_ctl(ep, EPOLL_CTL_DEL, fd, nullptr);
      close(fd);
      kinds.erase(fd);
      if (kind == Kind::Idle || kind == Kind::Slowloris) {
        ++reconnects_;
        open_one(kind);  // the attacker comes back at once
      } else {
        ++viewers_closed_;
      }
    }
    if (Clock::now() >= next_byte) {
      next_byte += mix_.slowloris_byte_period;
      for (const auto& [fd, kind] : kinds)
        if (kind == Kind::Slowloris) send_text(fd, "x");
    }
  }
  for (const auto& [fd, kind] : kinds) close(fd);
  close(ep);
}

std::optional<double> time_to_first_frame(int port, std::chrono::milliseconds timeout) {
  const auto start = Clock::now();
  const int fd = connect_to(port);
  if (fd < 0) return std::nullopt;
  send_text(fd, kStreamRequest);
  std::string got;
  std::optional<double> ms;
  char buf[16384];
  while (!ms && Clock::now() - start < timeout) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 20) <= 0) continue;
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    got.append(buf, static_cast<std::size_t>(n));
    // The first part: its Content-Length after the first boundary, then that many bytes.
    const auto len_at = got.find("Content-Length: ", got.find("--boundarydonotcross"));
    const auto body_at = got.find("\r\n\r\n", len_at);
    if (len_at == std::string::npos || body_at == std::string::npos) continue;
    const std::size_t length = std::stoul(got.substr(len_at + 16));
    // Chunk framing may add a few bytes inside; the JPEG's end marker says it is complete.
    if (got.size() >= body_at + 4 + length &&
        got.find("\xff\xd9", body_at + 4 + length - 2) != std::string::npos)
      ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  }
  close(fd);
  return ms;
}

int viewers_leaving_mid_frame(int port, int count, int batch, std::size_t bytes) {
  int served = 0;
  std::vector<char> buf(bytes);
  for (int done = 0; done < count; done += batch) {
    std::vector<int> fds;
    for (int i = 0; i < batch && done + i < count; ++i) {
      const int fd = connect_to(port);
      if (fd < 0) continue;
      send_text(fd, kStreamRequest);
      fds.push_back(fd);
    }
    for (const int fd : fds) {
      std::size_t got = 0;
      const auto deadline = Clock::now() + std::chrono::seconds(5);
      while (got < bytes && Clock::now() < deadline) {
        pollfd p{fd, POLLIN, 0};
        if (poll(&p, 1, 50) <= 0) continue;
        const ssize_t n = recv(fd, buf.data(), bytes - got, 0);
        if (n <= 0) break;
        got += static_cast<std::size_t>(n);
      }
      if (got >= bytes) ++served;
      reset_and_close(fd);
    }
  }
  return served;
}

long raise_descriptor_limit() {
  rlimit limit{};
  getrlimit(RLIMIT_NOFILE, &limit);
  limit.rlim_cur = limit.rlim_max;
  setrlimit(RLIMIT_NOFILE, &limit);
  getrlimit(RLIMIT_NOFILE, &limit);
  return static_cast<long>(limit.rlim_cur);
}

}  // namespace probeless::lab
