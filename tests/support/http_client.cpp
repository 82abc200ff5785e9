#include "support/http_client.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace probeless::testing::loopback {
namespace {

int connect_loopback(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error("socket failed");
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    throw std::runtime_error("connect to 127.0.0.1:" + std::to_string(port) + " failed");
  }
  return fd;
}

void send_request(int fd, const std::string& path) {
  const std::string req = "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n";
  if (::send(fd, req.data(), req.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(req.size()))
    throw std::runtime_error("send failed");
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// Splits "Name: value" into the map, lower-casing the name.
void add_header(std::map<std::string, std::string>& headers, const std::string& line) {
  const auto colon = line.find(':');
  if (colon == std::string::npos) return;
  std::string value = line.substr(colon + 1);
  value.erase(0, value.find_first_not_of(' '));
  headers[lower(line.substr(0, colon))] = value;
}

// Reads into `buffer` until it holds `want` bytes, the peer closes, or the deadline.
bool read_more(int fd, std::string& buffer, std::chrono::steady_clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
      deadline - std::chrono::steady_clock::now());
  if (left.count() <= 0) return false;
  pollfd p{fd, POLLIN, 0};
  if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) return false;
  char chunk[16384];
  const ssize_t n = ::recv(fd, chunk, sizeof chunk, 0);
  if (n <= 0) return false;
  buffer.append(chunk, static_cast<std::size_t>(n));
  return true;
}

}  // namespace

HttpResponse http_get(int port, const std::string& path, std::chrono::milliseconds timeout) {
  const int fd = connect_loopback(port);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::string data;
  try {
    send_request(fd, path);
    while (read_more(fd, data, deadline)) {
    }
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  const auto end = data.find("\r\n\r\n");
  if (end == std::string::npos) throw std::runtime_error("GET " + path + ": no complete reply");
  HttpResponse r;
  std::size_t pos = 0;
  bool first = true;
  while (pos < end) {
    const auto eol = data.find("\r\n", pos);
    const std::string line = data.substr(pos, eol - pos);
    if (first) {
      r.status = std::stoi(line.substr(line.find(' ') + 1, 3));
      first = false;
    } else {
      add_header(r.headers, line);
    }
    pos = eol + 2;
  }
  r.body = data.substr(end + 4);
  return r;
}

MjpegReader::MjpegReader(int port, const std::string& path) : fd_(connect_loopback(port)) {
  send_request(fd_, path);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  auto status = line(deadline);
  if (!status) throw std::runtime_error("GET " + path + ": no reply");
  while (auto l = line(deadline)) {
    if (l->empty()) break;
    add_header(headers_, *l);
  }
}

MjpegReader::~MjpegReader() { ::close(fd_); }

bool MjpegReader::fill(std::chrono::steady_clock::time_point deadline) {
  return read_more(fd_, buffer_, deadline);
}

std::optional<std::string> MjpegReader::line(std::chrono::steady_clock::time_point deadline) {
  for (;;) {
    const auto eol = buffer_.find("\r\n");
    if (eol != std::string::npos) {
      std::string l = buffer_.substr(0, eol);
      buffer_.erase(0, eol + 2);
      return l;
    }
    if (!fill(deadline)) return std::nullopt;
  }
}

std::optional<std::vector<std::uint8_t>> MjpegReader::next_part(
    std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  // Skip to the boundary line, then read the part's headers.
  for (;;) {
    auto l = line(deadline);
    if (!l) return std::nullopt;
    if (l->rfind("--", 0) == 0) break;
  }
  std::map<std::string, std::string> part;
  while (auto l = line(deadline)) {
    if (l->empty()) break;
    add_header(part, *l);
  }
  const auto it = part.find("content-length");
  if (it == part.end()) throw std::runtime_error("MJPEG part without Content-Length");
  const auto length = static_cast<std::size_t>(std::stoul(it->second));
  while (buffer_.size() < length)
    if (!fill(deadline)) return std::nullopt;
  std::vector<std::uint8_t> body(buffer_.begin(), buffer_.begin() + static_cast<long>(length));
  buffer_.erase(0, length);
  return body;
}

}  // namespace probeless::testing::loopback
