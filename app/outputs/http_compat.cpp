#include "app/outputs/http_compat.hpp"

#include <event2/http.h>
#include <event2/keyvalq_struct.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "app/outputs/banner.hpp"
#include "app/outputs/jpeg_encoder.hpp"

namespace probeless {
namespace {

bool flag_value(std::string_view v) {
  if (v == "true" || v == "yes") return true;
  if (v.empty() || v.size() > 9) return false;
  for (const char c : v)
    if (c < '0' || c > '9') return false;
  return std::strtol(std::string(v).c_str(), nullptr, 10) != 0;
}

// ustreamer prints rates as whole frames per second.
unsigned whole_fps(double fps) {
  return fps > 0 ? static_cast<unsigned>(std::lround(fps)) : 0u;
}

// ustreamer labels clients with the key; a long one is cut so /state stays small.
constexpr std::size_t kMaxKeyLength = 64;

}  // namespace

StreamOptions parse_stream_options(const char* query) {
  StreamOptions options;
  if (query == nullptr || *query == '\0') return options;
  evkeyvalq params{};
  if (evhttp_parse_query_str(query, &params) == 0) {
    for (const evkeyval* p = params.tqh_first; p != nullptr; p = p->next.tqe_next) {
      const std::string_view name(p->key);
      const std::string_view value(p->value);
      if (name == "key")
        options.key = std::string(value.substr(0, kMaxKeyLength));
      else if (name == "extra_headers")
        options.extra_headers = flag_value(value);
      else if (name == "advance_headers")
        options.advance_headers = flag_value(value);
      else if (name == "dual_final_frames")
        options.dual_final_frames = flag_value(value);
    }
  }
  evhttp_clear_headers(&params);
  return options;
}

std::string seconds_text(TimestampNs ns) {
  char text[40];
  const long long sign = ns < 0 ? -1 : 1;
  const long long abs_ns = static_cast<long long>(ns) * sign;
  std::snprintf(text, sizeof text, "%s%lld.%06lld", sign < 0 ? "-" : "", abs_ns / 1000000000,
                abs_ns % 1000000000 / 1000);
  return text;
}

TimestampNs wall_clock_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

TimestampNs wall_clock_ns(TimestampNs monotonic_ns) {
  return wall_clock_now_ns() - (monotonic_now_ns() - monotonic_ns);
}

std::string stream_part_head(const PartFrame& frame, bool extra, double client_fps) {
  std::string head =
      std::string("--") + kStreamBoundary +
      "\r\nContent-Type: image/jpeg\r\nContent-Length: " + std::to_string(frame.length) +
      "\r\nX-Timestamp: " + seconds_text(frame.capture_wall_ns) +
      "\r\nX-Timestamp-Monotonic: " + seconds_text(frame.capture_ns) + "\r\n";
  if (extra) {
    const TimestampNs now = wall_clock_now_ns();
    head += std::string("X-UStreamer-Online: ") + (frame.online ? "true" : "false") +
            "\r\nX-UStreamer-Width: " + std::to_string(frame.size.width) +
            "\r\nX-UStreamer-Height: " + std::to_string(frame.size.height) +
            "\r\nX-UStreamer-Client-FPS: " + std::to_string(whole_fps(client_fps)) +
            "\r\nX-UStreamer-Grab-Time: " + seconds_text(frame.capture_wall_ns) +
            "\r\nX-UStreamer-Send-Time: " + seconds_text(now) +
            "\r\nX-UStreamer-Latency: " + seconds_text(now - frame.capture_wall_ns) + "\r\n";
  }
  return head + "\r\n";
}

std::string advance_part_head() {
  return std::string("--") + kStreamBoundary +
         "\r\nContent-Type: image/jpeg\r\nX-Timestamp: " + seconds_text(wall_clock_now_ns()) +
         "\r\n\r\n";
}

std::optional<JpegSize> jpeg_size(std::span<const std::uint8_t> jpeg) {
  if (jpeg.size() < 4 || jpeg[0] != 0xFF || jpeg[1] != 0xD8) return std::nullopt;
  std::size_t at = 2;
  while (at + 4 <= jpeg.size()) {
    if (jpeg[at] != 0xFF) return std::nullopt;
    const std::uint8_t marker = jpeg[at + 1];
    if (marker == 0xFF) {  // fill byte before a marker
      ++at;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {  // no length
      at += 2;
      continue;
    }
    if (marker == 0xD9 || marker == 0xDA) return std::nullopt;  // end or scan before a frame
    const std::size_t length = std::size_t{jpeg[at + 2]} << 8 | jpeg[at + 3];
    if (length < 2 || at + 2 + length > jpeg.size()) return std::nullopt;
    // SOF0..SOF15 except DHT (C4), JPG (C8) and DAC (CC): length, precision, height, width.
    const bool frame =
        marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame) {
      if (length < 7) return std::nullopt;
      const int height = jpeg[at + 5] << 8 | jpeg[at + 6];
      const int width = jpeg[at + 7] << 8 | jpeg[at + 8];
      if (width == 0 || height == 0) return std::nullopt;
      return JpegSize{width, height};
    }
    at += 2 + length;
  }
  return std::nullopt;
}

std::shared_ptr<const std::vector<std::uint8_t>> placeholder_jpeg(int width, int height,
                                                                  int quality) {
  ImageRGB8 image(width, height);
  draw_no_signal(image, "", "waiting for the first frame");
  JpegEncoder encoder(quality);
  return encoder.encode_shared(image);
}

nlohmann::json to_json(const UstreamerState& state) {
  nlohmann::json clients = nlohmann::json::object();
  for (const auto& c : state.clients) {
    clients[c.id] = {{"key", c.options.key},
                     {"fps", whole_fps(c.fps)},
                     {"extra_headers", c.options.extra_headers},
                     {"advance_headers", c.options.advance_headers},
                     {"dual_final_frames", c.options.dual_final_frames},
                     {"zero_data", false}};
  }
  const nlohmann::json source = {
      {"resolution", {{"width", state.resolution.width}, {"height", state.resolution.height}}},
      {"online", state.online},
      {"desired_fps", whole_fps(state.desired_fps)},
      {"captured_fps", whole_fps(state.captured_fps)}};
  const nlohmann::json stream = {{"queued_fps", whole_fps(state.queued_fps)},
                                 {"clients", state.clients.size()},
                                 {"clients_stat", std::move(clients)}};
  return {{"ok", true},
          {"result",
           {{"instance_id", ""},
            {"encoder", {{"type", "CPU"}, {"quality", state.quality}}},
            {"source", source},
            {"stream", stream}}}};
}

}  // namespace probeless
