#pragma once
// Pacing and looping shared by the file sources (recordings, TUM sequences). A Playback walks
// one stream's timestamps and says which frame read() should deliver, if any yet.
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/time.hpp"
#include "drivers/source.hpp"

namespace probeless::replay {

struct PlaybackOptions {
  // true: frames are delivered when their recorded time has come (relative to the first
  // read), and frames a slow reader missed are skipped, as a camera would; false: every frame
  // in order, as fast as they are read.
  bool realtime = true;
  // Start again after the last frame; sequence numbers and timestamps keep increasing.
  bool loop = false;
  // Shift timestamps so that the first frame carries the time of the first read
  // (CLOCK_MONOTONIC), as a live source's would.
  bool rebase = false;
  // The RGB-D frame's (rebased) capture time drawn into its colour image as a binary code
  // (core/capture_stamp.hpp), for the glass-to-glass latency bench. Needs `rebase`: a
  // recorded timestamp is on the clock of the boot that recorded it.
  bool stamp = false;
};

// Parses "realtime=0,loop=1,rebase=1,stamp=1" (',' or '&' between items); other keys are
// returned in `rest` as key/value pairs for the caller. Throws std::invalid_argument naming a
// bad value, or `stamp` without `rebase`.
PlaybackOptions parse_playback_options(std::string_view spec,
                                       std::vector<std::pair<std::string, std::string>>* rest);

// Wall-clock origin shared by the streams of one recording, so that their frames keep their
// recorded relative timing. Starts at the first call of either stream.
class PlaybackClock {
 public:
  explicit PlaybackClock(TimestampNs recording_start_ns)
      : recording_start_ns_(recording_start_ns) {}
  // CLOCK_MONOTONIC time at which recorded time `t` is due.
  TimestampNs due_ns(TimestampNs t);
  // Offset added to timestamps when rebasing (starts the clock).
  TimestampNs rebase_offset_ns();

 private:
  TimestampNs wall_start_locked();
  std::mutex mutex_;
  std::optional<TimestampNs> wall_start_ns_;
  TimestampNs recording_start_ns_;
};

class Playback {
 public:
  struct Next {
    ReadResult result = ReadResult::NoFrameYet;
    std::size_t index = 0;              // entry to deliver (result == Frame)
    std::uint64_t sequence_offset = 0;  // add to the recorded sequence
    TimestampNs timestamp_offset = 0;   // add to the recorded timestamp
  };

  // `timestamps` and `sequences` of the stream's entries, in order. `loop_span_ns` is how far
  // one pass advances the timestamps when looping.
  Playback(std::vector<TimestampNs> timestamps, std::vector<std::uint64_t> sequences,
           PlaybackOptions options, std::shared_ptr<PlaybackClock> clock, TimestampNs loop_span_ns);

  // Blocks at most `timeout` (until the next frame is due in realtime mode).
  Next next(std::chrono::milliseconds timeout);
  SourceState state() const { return state_; }
  const PlaybackOptions& options() const { return options_; }

 private:
  TimestampNs shifted(std::size_t index, std::int64_t pass) const;
  std::vector<TimestampNs> timestamps_;
  std::vector<std::uint64_t> sequences_;
  PlaybackOptions options_;
  std::shared_ptr<PlaybackClock> clock_;
  TimestampNs loop_span_ns_;
  std::uint64_t sequence_span_ = 0;
  std::size_t index_ = 0;
  std::int64_t pass_ = 0;
  SourceState state_ = SourceState::Streaming;
};

}  // namespace probeless::replay
