#pragma once
// A deliberately plain HTTP/1.x client over a blocking loopback socket, for testing the
// server as a real client sees it: status line, headers, chunked transfer decoding and the
// multipart/x-mixed-replace parts of an MJPEG stream.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace probeless::testing {

inline std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

class TcpClient {
 public:
  // receive_buffer > 0 shrinks SO_RCVBUF before connecting (a client that fills up fast).
  explicit TcpClient(int port, int receive_buffer = 0) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw std::runtime_error("socket");
    if (receive_buffer > 0) {
      ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
    }
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      ::close(fd_);
      throw std::runtime_error("connect");
    }
  }
  ~TcpClient() {
    if (fd_ >= 0) ::close(fd_);
  }
  TcpClient(const TcpClient&) = delete;
  TcpClient& operator=(const TcpClient&) = delete;

  void send_all(std::string_view data) {
    while (!data.empty()) {
      const ssize_t n = ::send(fd_, data.data(), data.size(), MSG_NOSIGNAL);
      if (n <= 0) throw std::runtime_error("send");
      data.remove_prefix(static_cast<std::size_t>(n));
    }
  }

  // Appends what arrives within `timeout` (at least one read) to `out`; false on timeout
  // or end of stream.
  bool receive(std::string& out, std::chrono::milliseconds timeout) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return false;
    char buf[65536];
    const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
    if (n <= 0) {
      eof_ = true;
      return false;
    }
    out.append(buf, static_cast<std::size_t>(n));
    return true;
  }
  bool eof() const { return eof_; }
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
  bool eof_ = false;
};

struct HttpHead {
  std::string version;
  int status = 0;
  std::map<std::string, std::string> headers;  // lower-case names
  bool has(const std::string& name) const { return headers.count(name) != 0; }
  std::string get(const std::string& name) const {
    auto it = headers.find(name);
    return it == headers.end() ? std::string() : it->second;
  }
};

// Parses "HTTP/1.1 200 OK\r\nName: value\r\n...\r\n\r\n" from the front of `buffer`.
inline std::optional<HttpHead> parse_head(std::string& buffer) {
  const auto end = buffer.find("\r\n\r\n");
  if (end == std::string::npos) return std::nullopt;
  HttpHead head;
  std::string_view text(buffer.data(), end);
  const auto line_end = text.find("\r\n");
  const std::string_view status_line = text.substr(0, line_end);
  head.version = std::string(status_line.substr(0, status_line.find(' ')));
  head.status = std::stoi(std::string(status_line.substr(status_line.find(' ') + 1, 3)));
  std::size_t pos = line_end == std::string_view::npos ? text.size() : line_end + 2;
  while (pos < text.size()) {
    auto next = text.find("\r\n", pos);
    if (next == std::string_view::npos) next = text.size();
    const std::string_view line = text.substr(pos, next - pos);
    const auto colon = line.find(':');
    if (colon != std::string_view::npos) {
      std::string value(line.substr(colon + 1));
      value.erase(0, value.find_first_not_of(' '));
      head.headers[lower(std::string(line.substr(0, colon)))] = value;
    }
    pos = next + 2;
  }
  buffer.erase(0, end + 4);
  return head;
}

// Moves complete chunks from `raw` to `out`; true once the last (zero) chunk was seen.
inline bool dechunk(std::string& raw, std::string& out) {
  for (;;) {
    const auto eol = raw.find("\r\n");
    if (eol == std::string::npos) return false;
    const std::size_t size = std::stoul(raw.substr(0, eol), nullptr, 16);
    if (size == 0) return true;
    if (raw.size() < eol + 2 + size + 2) return false;
    if (raw.compare(eol + 2 + size, 2, "\r\n") != 0) throw std::runtime_error("bad chunk");
    out.append(raw, eol + 2, size);
    raw.erase(0, eol + 2 + size + 2);
  }
}

struct HttpResponse {
  HttpHead head;
  std::string body;
};

// One request on a fresh connection, the request head as given (with its blank line), read
// to the end.
inline HttpResponse http_exchange(int port, const std::string& request,
                                  std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
  TcpClient client(port);
  client.send_all(request);
  std::string raw;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::optional<HttpHead> head;
  while (!client.eof() && std::chrono::steady_clock::now() < deadline) {
    client.receive(raw, std::chrono::milliseconds(100));
    if (!head) head = parse_head(raw);
  }
  if (!head) throw std::runtime_error("no response head for " + request.substr(0, 40));
  HttpResponse r{*head, {}};
  if (lower(r.head.get("transfer-encoding")) == "chunked") {
    dechunk(raw, r.body);
  } else {
    r.body = raw;
  }
  return r;
}

// One request on a fresh connection ("Connection: close"); `headers`: extra header lines,
// each ending in CRLF.
inline HttpResponse http_request(int port, const std::string& method, const std::string& target,
                                 std::chrono::milliseconds timeout = std::chrono::seconds(5),
                                 const std::string& headers = "Host: localhost\r\n") {
  return http_exchange(
      port, method + " " + target + " HTTP/1.1\r\n" + headers + "Connection: close\r\n\r\n",
      timeout);
}

inline HttpResponse http_get(int port, const std::string& target) {
  return http_request(port, "GET", target);
}

struct MjpegPart {
  std::map<std::string, std::string> headers;  // lower-case names
  std::string body;
};

// Reads an MJPEG stream part by part, checking the framing as it goes.
class MjpegReader {
 public:
  MjpegReader(int port, const std::string& target, bool http10 = false) : client_(port) {
    client_.send_all("GET " + target + (http10 ? " HTTP/1.0\r\n" : " HTTP/1.1\r\n") +
                     "Host: localhost\r\n\r\n");
  }

  // The response head (waits for it); throws when it does not come.
  const HttpHead& head(std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!head_ && std::chrono::steady_clock::now() < deadline) {
      if (!client_.receive(raw_, std::chrono::milliseconds(100)) && client_.eof()) break;
      head_ = parse_head(raw_);
    }
    if (!head_) throw std::runtime_error("no stream response head");
    chunked_ = lower(head_->get("transfer-encoding")) == "chunked";
    const std::string type = head_->get("content-type");
    const auto at = type.find("boundary=");
    if (at != std::string::npos) boundary_ = type.substr(at + 9);
    return *head_;
  }

  std::optional<MjpegPart> next(std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    head();
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      if (auto part = parse_part()) return part;
      if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
      if (!client_.receive(raw_, std::chrono::milliseconds(50)) && client_.eof()) {
        return std::nullopt;
      }
      if (chunked_) {
        dechunk(raw_, body_);
      } else {
        body_ += raw_;
        raw_.clear();
      }
    }
  }

  const std::string& boundary() const { return boundary_; }
  bool chunked() const { return chunked_; }
  bool closed() const { return client_.eof(); }  // the server ended the stream (or reset it)

 private:
  std::optional<MjpegPart> parse_part() {
    if (!chunked_ && !raw_.empty()) {  // bytes that arrived with the head
      body_ += raw_;
      raw_.clear();
    } else if (chunked_) {
      dechunk(raw_, body_);
    }
    const std::string delimiter = "--" + boundary_ + "\r\n";
    std::size_t start = 0;
    if (body_.compare(0, 2, "\r\n") == 0) start = 2;
    if (body_.size() < start + delimiter.size()) return std::nullopt;
    if (body_.compare(start, delimiter.size(), delimiter) != 0) {
      throw std::runtime_error("part does not start with the boundary");
    }
    const auto head_end = body_.find("\r\n\r\n", start);
    if (head_end == std::string::npos) return std::nullopt;
    MjpegPart part;
    std::size_t pos = start + delimiter.size();
    while (pos < head_end) {
      const auto eol = body_.find("\r\n", pos);
      const std::string line = body_.substr(pos, eol - pos);
      const auto colon = line.find(':');
      if (colon != std::string::npos) {
        std::string value = line.substr(colon + 1);
        value.erase(0, value.find_first_not_of(' '));
        part.headers[lower(line.substr(0, colon))] = value;
      }
      pos = eol + 2;
    }
    const auto length_it = part.headers.find("content-length");
    if (length_it == part.headers.end()) throw std::runtime_error("part without Content-Length");
    const std::size_t length = std::stoul(length_it->second);
    const std::size_t data_start = head_end + 4;
    if (body_.size() < data_start + length + 2) return std::nullopt;
    part.body = body_.substr(data_start, length);
    if (body_.compare(data_start + length, 2, "\r\n") != 0) {
      throw std::runtime_error("part data not followed by CRLF");
    }
    body_.erase(0, data_start + length + 2);
    return part;
  }

  TcpClient client_;
  std::string raw_;   // as received
  std::string body_;  // after transfer decoding
  std::optional<HttpHead> head_;
  bool chunked_ = false;
  std::string boundary_;
};

}  // namespace probeless::testing
