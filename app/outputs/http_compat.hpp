#pragma once
// What the HTTP server needs to answer a ustreamer (pikvm/ustreamer) client as ustreamer
// would (issue #22 item 2), kept apart from libevent so each piece is tested on plain values:
// the options a stream URL carries, wall-clock timestamps, the part and snapshot headers,
// the JPEG's size, the placeholder shown before the first frame and the /state object.
// docs/outputs.md "ustreamer compatibility" has the table of what matches.
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/time.hpp"

namespace probeless {

// ustreamer's /stream query parameters. `key` only labels the client in /state.
struct StreamOptions {
  std::string key;
  bool extra_headers = false;      // X-UStreamer-* headers in every part
  bool advance_headers = false;    // the next part's headers right after each frame
  bool dual_final_frames = false;  // accepted and reported; see docs/outputs.md
};

// From a request's query string (null or empty: the defaults). A flag is on when its value
// is a number other than 0 or "true"/"yes", as ustreamer reads them.
StreamOptions parse_stream_options(const char* query);

// Seconds with microseconds, "1700000000.123456", as ustreamer prints X-Timestamp.
std::string seconds_text(TimestampNs ns);

// A CLOCK_MONOTONIC time as wall-clock (CLOCK_REALTIME) nanoseconds, through the two
// clocks' offset now: a step of the wall clock (NTP) moves later conversions with it.
TimestampNs wall_clock_ns(TimestampNs monotonic_ns);
TimestampNs wall_clock_now_ns();

struct JpegSize {
  int width = 0;
  int height = 0;
};

// The frame size from the JPEG's start-of-frame segment, reading only its markers; nullopt
// for anything that is not a well-formed JPEG up to that segment.
std::optional<JpegSize> jpeg_size(std::span<const std::uint8_t> jpeg);

// ustreamer's blank frame: black with "NO SIGNAL", what /snapshot serves before the pipeline
// has produced a frame (ustreamer answers 200 with it rather than an error).
std::shared_ptr<const std::vector<std::uint8_t>> placeholder_jpeg(int width, int height,
                                                                  int quality);

// mjpg-streamer's boundary, which ustreamer kept: some clients were written against it.
inline constexpr const char* kStreamBoundary = "boundarydonotcross";

// One stream part's frame, as its headers describe it.
struct PartFrame {
  std::size_t length = 0;
  TimestampNs capture_ns = 0;       // CLOCK_MONOTONIC
  TimestampNs capture_wall_ns = 0;  // the same instant on the wall clock
  bool online = true;
  JpegSize size;
};

// "--boundary", the part's headers and the blank line: X-Timestamp the capture time on the
// wall clock (ustreamer's), X-Timestamp-Monotonic on the monotonic clock (probeless's older
// X-Timestamp); with `extra`, ustreamer's X-UStreamer-* headers (send time = now).
std::string stream_part_head(const PartFrame& frame, bool extra, double client_fps);

// advance_headers: the next part's headers, sent right after a frame so that a client
// that shows a frame only once the next boundary arrives shows it at once. Without the
// length (not known yet) and with X-Timestamp the time they are sent, as ustreamer does.
std::string advance_part_head();

// What /state reports, gathered by the server.
struct UstreamerClient {
  std::string id;
  double fps = 0;
  StreamOptions options;
};
struct UstreamerState {
  int quality = 0;
  JpegSize resolution;
  bool online = false;
  double desired_fps = 0;  // 0: as fast as the source goes (ustreamer's --desired-fps default)
  double captured_fps = 0;
  double queued_fps = 0;
  std::vector<UstreamerClient> clients;
};

// {"ok": true, "result": {"instance_id": "", "encoder": ..., "source": ..., "stream": ...}}
nlohmann::json to_json(const UstreamerState& state);

}  // namespace probeless
