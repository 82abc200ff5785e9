// HTTP request handling through the real server loop (app/outputs/http_server.hpp): two
// HttpServers on ephemeral loopback ports, started once per process, one open (with a CORS
// origin) and one behind basic auth (user "fuzz", password "fuzz"). The input is sent as the
// raw bytes of one connection, the write side is shut, and the response is read until the
// server closes or 100 ms pass without a byte (a stream keeps its connection open). Inputs
// that carry an Authorization header go to both servers. The status callback serves the
// input's first bytes as a string, as a device or file name with any bytes would reach it.
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>

#include "app/outputs/http_server.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

namespace {

std::mutex last_input_mutex;
std::string last_input;

std::unique_ptr<HttpServer> start(HttpAuth auth) {
  HttpServerConfig config;
  config.port = 0;
  config.request_timeout = std::chrono::seconds(2);
  config.stalled_client_timeout = std::chrono::seconds(2);
  config.access.auth = auth;
  config.access.user = "fuzz";
  config.access.password = "fuzz";
  config.access.cors_origin = "https://dashboard.local";
  auto server = std::make_unique<HttpServer>(config, [] {
    std::lock_guard lock(last_input_mutex);
    return nlohmann::json{{"state", "running"}, {"last_error", last_input}};
  });
  // A frame, so that /snapshot and /stream have something to send (never decoded).
  auto jpeg = std::make_shared<const std::vector<std::uint8_t>>(
      std::vector<std::uint8_t>{0xff, 0xd8, 0xff, 0xd9});
  server->publish({jpeg, 1});
  return server;
}

void exchange(int port, std::string_view request) {
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::logic_error("socket failed");
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  // Closed with a reset, not a FIN: this side would otherwise keep every connection in
  // TIME_WAIT for a minute, and at ~2000 inputs a second the loopback's ephemeral ports ran
  // out after 30 s (connect: EADDRNOTAVAIL).
  const linger reset{1, 0};
  setsockopt(fd, SOL_SOCKET, SO_LINGER, &reset, sizeof reset);
  int connected = connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
  if (connected != 0 && errno == EINTR) {  // libFuzzer's SIGALRM: the connect goes on
    pollfd p{fd, POLLOUT, 0};
    while (poll(&p, 1, 1000) < 0 && errno == EINTR) {
    }
    int error = 0;
    socklen_t length = sizeof error;
    getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length);
    connected = error == 0 ? 0 : -1;
    errno = error;
  }
  if (connected != 0) {
    const int error = errno;
    close(fd);
    throw std::logic_error(std::string("connect to the fuzzed server failed: ") +
                           std::strerror(error));
  }
  std::size_t sent = 0;
  while (sent < request.size()) {
    const ssize_t n = send(fd, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the server may close before reading everything (a bad request)
    sent += static_cast<std::size_t>(n);
  }
  shutdown(fd, SHUT_WR);
  char buffer[16384];
  std::size_t received = 0;
  std::string_view head;
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    const int ready = poll(&p, 1, 100);
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) break;
    const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    if (received == 0) head = std::string_view(buffer, static_cast<std::size_t>(n)).substr(0, 40);
    received += static_cast<std::size_t>(n);
  }
  close(fd);
  if (std::getenv("PROBELESS_FUZZ_VERBOSE"))  // what the seeds get back, when writing them
    std::fprintf(stderr, "%zu bytes: %.*s\n", received, static_cast<int>(head.size()), head.data());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto open_server = start(HttpAuth::None);
  static const auto auth_server = start(HttpAuth::Basic);
  const std::string_view request = fuzz::as_text(data, size);
  {
    std::lock_guard lock(last_input_mutex);
    last_input.assign(request.substr(0, 16));
  }
  exchange(open_server->port(), request);
  if (request.find("uthorization") != std::string_view::npos)
    exchange(auth_server->port(), request);
  return 0;
}
