#pragma once
// An MJPEG viewer for the latency bench: GET /stream?extra_headers=1 over loopback as
// HTTP/1.0 (the multipart body raw, as mjpg-streamer clients read it), each part's JPEG
// decoded with TurboJPEG (app/outputs/jpeg_encoder.hpp) as soon as its last byte is in.
#include <string>

#include "app/outputs/jpeg_encoder.hpp"
#include "base/unique_fd.hpp"
#include "lab/bench/frame_receiver.hpp"

namespace probeless::lab {

class MjpegReceiver final : public FrameReceiver {
 public:
  // Connects to 127.0.0.1:port and sends the request; throws std::runtime_error.
  explicit MjpegReceiver(int port);
  std::optional<ReceivedFrame> next(std::chrono::milliseconds timeout) override;

 private:
  // Reads more of the stream into buffer_; false on timeout.
  bool fill(TimestampNs deadline_ns);

  UniqueFd socket_;
  std::string buffer_;  // received and not yet parsed
  bool headers_done_ = false;
  JpegDecoder decoder_;
};

}  // namespace probeless::lab
