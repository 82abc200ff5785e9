#include "drivers/replay/playback.hpp"

#include <algorithm>
#include <stdexcept>
#include <thread>

namespace probeless::replay {

namespace {

bool parse_bool(const std::string& key, const std::string& value) {
  if (value == "1" || value == "true" || value == "on" || value == "yes") return true;
  if (value == "0" || value == "false" || value == "off" || value == "no") return false;
  throw std::invalid_argument("option " + key + ": '" + value + "' is not a boolean (use 0 or 1)");
}

}  // namespace

PlaybackOptions parse_playback_options(std::string_view spec,
                                       std::vector<std::pair<std::string, std::string>>* rest) {
  PlaybackOptions options;
  std::size_t start = 0;
  while (start <= spec.size()) {
    std::size_t end = spec.find_first_of(",&", start);
    if (end == std::string_view::npos) end = spec.size();
    const std::string_view item = spec.substr(start, end - start);
    start = end + 1;
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    const std::string key(item.substr(0, eq));
    const std::string value(eq == std::string_view::npos ? "1" : item.substr(eq + 1));
    if (key == "realtime")
      options.realtime = parse_bool(key, value);
    else if (key == "loop")
      options.loop = parse_bool(key, value);
    else if (key == "rebase")
      options.rebase = parse_bool(key, value);
    else if (key == "stamp")
      options.stamp = parse_bool(key, value);
    else if (rest)
      rest->emplace_back(key, value);
    else
      throw std::invalid_argument("unknown option '" + key +
                                  "' (known: realtime, loop, rebase, stamp)");
  }
  // Without rebase the stamp would carry another boot's clock and every latency read from it
  // would be nonsense rather than missing.
  if (options.stamp && !options.rebase)
    throw std::invalid_argument(
        "option stamp=1 needs rebase=1 (the stamp is the capture time on this machine's "
        "clock)");
  return options;
}

TimestampNs PlaybackClock::wall_start_locked() {
  if (!wall_start_ns_) wall_start_ns_ = monotonic_now_ns();
  return *wall_start_ns_;
}

TimestampNs PlaybackClock::due_ns(TimestampNs t) {
  std::lock_guard lock(mutex_);
  return wall_start_locked() + (t - recording_start_ns_);
}

TimestampNs PlaybackClock::rebase_offset_ns() {
  std::lock_guard lock(mutex_);
  return wall_start_locked() - recording_start_ns_;
}

Playback::Playback(std::vector<TimestampNs> timestamps, std::vector<std::uint64_t> sequences,
                   PlaybackOptions options, std::shared_ptr<PlaybackClock> clock,
                   TimestampNs loop_span_ns)
    : timestamps_(std::move(timestamps)),
      sequences_(std::move(sequences)),
      options_(options),
      clock_(std::move(clock)),
      loop_span_ns_(loop_span_ns) {
  if (timestamps_.size() != sequences_.size()) {
    throw std::invalid_argument("Playback: timestamps and sequences differ in length");
  }
  if (!sequences_.empty()) {
    const auto [lo, hi] = std::minmax_element(sequences_.begin(), sequences_.end());
    sequence_span_ = *hi - *lo + 1;
  }
  if (timestamps_.empty()) state_ = SourceState::Ended;
}

TimestampNs Playback::shifted(std::size_t index, std::int64_t pass) const {
  return timestamps_[index] + pass * loop_span_ns_;
}

Playback::Next Playback::next(std::chrono::milliseconds timeout) {
  Next out;
  if (index_ >= timestamps_.size()) {
    if (!options_.loop || timestamps_.empty()) {
      state_ = SourceState::Ended;
      out.result = ReadResult::EndOfStream;
      return out;
    }
    index_ = 0;
    ++pass_;
  }
  if (options_.realtime) {
    const TimestampNs now = monotonic_now_ns();
    // Skip what a slow reader missed: deliver the latest frame already due.
    while (true) {
      std::size_t next_index = index_ + 1;
      std::int64_t next_pass = pass_;
      if (next_index >= timestamps_.size()) {
        if (!options_.loop) break;
        next_index = 0;
        ++next_pass;
      }
      if (clock_->due_ns(shifted(next_index, next_pass)) > now) break;
      index_ = next_index;
      pass_ = next_pass;
    }
    const TimestampNs wait = clock_->due_ns(shifted(index_, pass_)) - now;
    if (wait > 0) {
      const auto limit = std::chrono::duration_cast<std::chrono::nanoseconds>(timeout).count();
      std::this_thread::sleep_for(std::chrono::nanoseconds(std::min<TimestampNs>(wait, limit)));
      if (wait > limit) {
        out.result = ReadResult::NoFrameYet;
        return out;
      }
    }
  }
  out.result = ReadResult::Frame;
  out.index = index_;
  out.sequence_offset = static_cast<std::uint64_t>(pass_) * sequence_span_;
  out.timestamp_offset = pass_ * loop_span_ns_ + (options_.rebase ? clock_->rebase_offset_ns() : 0);
  state_ = SourceState::Streaming;
  ++index_;
  return out;
}

}  // namespace probeless::replay
