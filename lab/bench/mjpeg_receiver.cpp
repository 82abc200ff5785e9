#include "lab/bench/mjpeg_receiver.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>

#include "app/outputs/http_compat.hpp"

namespace probeless::lab {
namespace {

// The server's own boundary (app/outputs/http_compat.hpp), with the "--" a part starts with.
const std::string kBoundary = std::string("--") + kStreamBoundary;
// A part larger than this is not a 640x480..4K frame at any quality: the stream is broken.
constexpr std::size_t kMaxPartBytes = 16u << 20;

// The value of header `name` (case-insensitive) in `headers`, "" when absent.
std::string header_value(std::string_view headers, std::string_view name) {
  std::size_t at = 0;
  while (at < headers.size()) {
    std::size_t end = headers.find("\r\n", at);
    if (end == std::string_view::npos) end = headers.size();
    const std::string_view line = headers.substr(at, end - at);
    at = end + 2;
    const std::size_t colon = line.find(':');
    if (colon != name.size()) continue;
    if (!std::equal(name.begin(), name.end(), line.begin(), [](char a, char b) {
          return std::tolower(static_cast<unsigned char>(a)) ==
                 std::tolower(static_cast<unsigned char>(b));
        }))
      continue;
    std::string_view value = line.substr(colon + 1);
    while (!value.empty() && value.front() == ' ') value.remove_prefix(1);
    return std::string(value);
  }
  return "";
}

}  // namespace

MjpegReceiver::MjpegReceiver(int port) : socket_(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0)) {
  if (!socket_) throw std::runtime_error(std::string("mjpeg: socket: ") + std::strerror(errno));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(socket_.get(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0)
    throw std::runtime_error("mjpeg: connect to port " + std::to_string(port) + ": " +
                             std::strerror(errno));
  // extra_headers: ustreamer's per-part X-UStreamer-Latency, the service's own share.
  const std::string request = "GET /stream?extra_headers=1 HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n";
  if (send(socket_.get(), request.data(), request.size(), MSG_NOSIGNAL) !=
      static_cast<ssize_t>(request.size()))
    throw std::runtime_error(std::string("mjpeg: send: ") + std::strerror(errno));
}

bool MjpegReceiver::fill(TimestampNs deadline_ns) {
  const TimestampNs left_ns = deadline_ns - monotonic_now_ns();
  if (left_ns <= 0) return false;
  pollfd p{socket_.get(), POLLIN, 0};
  const int ready = poll(&p, 1, static_cast<int>((left_ns + 999'999) / 1'000'000));
  if (ready < 0 && errno != EINTR)
    throw std::runtime_error(std::string("mjpeg: poll: ") + std::strerror(errno));
  if (ready <= 0) return false;
  char chunk[65536];
  const ssize_t n = recv(socket_.get(), chunk, sizeof chunk, 0);
  if (n == 0) throw std::runtime_error("mjpeg: the service closed the stream");
  if (n < 0) {
    if (errno == EINTR || errno == EAGAIN) return true;
    throw std::runtime_error(std::string("mjpeg: recv: ") + std::strerror(errno));
  }
  buffer_.append(chunk, static_cast<std::size_t>(n));
  if (buffer_.size() > 2 * kMaxPartBytes)
    throw std::runtime_error("mjpeg: no complete part in 32 MiB of stream");
  return true;
}

std::optional<ReceivedFrame> MjpegReceiver::next(std::chrono::milliseconds timeout) {
  const TimestampNs deadline = monotonic_now_ns() + ms_to_ns(timeout.count());
  while (!headers_done_) {
    if (const std::size_t end = buffer_.find("\r\n\r\n"); end != std::string::npos) {
      if (buffer_.compare(0, 12, "HTTP/1.0 200") != 0 &&
          buffer_.compare(0, 12, "HTTP/1.1 200") != 0)
        throw std::runtime_error("mjpeg: " + buffer_.substr(0, buffer_.find("\r\n")));
      buffer_.erase(0, end + 4);
      headers_done_ = true;
    } else if (!fill(deadline)) {
      return std::nullopt;
    }
  }
  for (;;) {
    const std::size_t start = buffer_.find(kBoundary);
    const std::size_t head_end =
        start == std::string::npos ? std::string::npos : buffer_.find("\r\n\r\n", start);
    if (head_end != std::string::npos) {
      const std::string_view head = std::string_view(buffer_).substr(start, head_end + 2 - start);
      const std::string length_text = header_value(head, "Content-Length");
      char* end = nullptr;
      const unsigned long long length = std::strtoull(length_text.c_str(), &end, 10);
      if (length_text.empty() || *end != '\0' || length == 0 || length > kMaxPartBytes)
        throw std::runtime_error("mjpeg: a part with Content-Length '" + length_text + "'");
      const std::size_t body = head_end + 4;
      if (buffer_.size() >= body + length) {
        ReceivedFrame frame;
        const std::string latency = header_value(head, "X-UStreamer-Latency");
        if (!latency.empty()) frame.service_ms = std::strtod(latency.c_str(), nullptr) * 1e3;
        frame.image = decoder_.decode(
            std::span(reinterpret_cast<const std::uint8_t*>(buffer_.data()) + body, length));
        frame.decoded_ns = monotonic_now_ns();
        buffer_.erase(0, body + length);
        return frame;
      }
    }
    if (!fill(deadline)) return std::nullopt;
  }
}

}  // namespace probeless::lab
