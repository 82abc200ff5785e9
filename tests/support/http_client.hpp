#pragma once
// A minimal blocking HTTP/1.1 client over loopback for end-to-end tests. It speaks
// HTTP/1.0, as mjpg-streamer clients do, so replies come unchunked until the server closes: one GET, and an
// MJPEG reader that returns the parts of a multipart/x-mixed-replace stream one by one.
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace probeless::testing::loopback {

struct HttpResponse {
  int status = 0;
  std::map<std::string, std::string> headers;  // names lower-cased
  std::string body;
};

// Throws std::runtime_error when the connection fails or times out.
HttpResponse http_get(int port, const std::string& path,
                      std::chrono::milliseconds timeout = std::chrono::seconds(10));

class MjpegReader {
 public:
  MjpegReader(int port, const std::string& path = "/stream");
  ~MjpegReader();
  MjpegReader(const MjpegReader&) = delete;
  MjpegReader& operator=(const MjpegReader&) = delete;

  const std::map<std::string, std::string>& headers() const { return headers_; }
  // The next part's body (a JPEG), nullopt at end of stream or timeout.
  std::optional<std::vector<std::uint8_t>> next_part(std::chrono::milliseconds timeout);

 private:
  bool fill(std::chrono::steady_clock::time_point deadline);
  std::optional<std::string> line(std::chrono::steady_clock::time_point deadline);
  int fd_ = -1;
  std::string buffer_;
  std::map<std::string, std::string> headers_;
};

}  // namespace probeless::testing::loopback
