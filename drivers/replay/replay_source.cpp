#include "drivers/replay/replay_source.hpp"

#include "core/capture_stamp.hpp"
#include "drivers/io/png.hpp"

namespace probeless::replay {
namespace {

template <typename Entry>
Playback make_playback(const std::vector<Entry>& entries, const Recording& recording,
                       const PlaybackOptions& options, std::shared_ptr<PlaybackClock> clock) {
  std::vector<TimestampNs> timestamps;
  std::vector<std::uint64_t> sequences;
  for (const Entry& e : entries) {
    timestamps.push_back(e.timestamp_ns);
    sequences.push_back(e.sequence);
  }
  if (!clock) clock = std::make_shared<PlaybackClock>(recording.start_ns());
  return Playback(std::move(timestamps), std::move(sequences), options, std::move(clock),
                  recording.loop_span_ns());
}

// Loads entry `next.index` into `frame` with the pass's offsets; Error on a bad image.
template <typename FrameT, typename Entry>
ReadResult deliver(const Playback::Next& next, const std::vector<Entry>& entries,
                   FrameLoader& loader, FrameT& frame, std::string& last_error) {
  if (next.result != ReadResult::Frame) return next.result;
  try {
    frame = loader.load(entries[next.index]);
  } catch (const ImageFileError& e) {
    last_error = e.what();
    return ReadResult::Error;
  }
  frame.sequence += next.sequence_offset;
  frame.timestamp_ns += next.timestamp_offset;
  return ReadResult::Frame;
}

}  // namespace

ReplayRgbdSource::ReplayRgbdSource(std::shared_ptr<const Recording> recording,
                                   PlaybackOptions options, std::shared_ptr<PlaybackClock> clock)
    : recording_(recording),
      playback_(make_playback(recording->rgbd(), *recording, options, std::move(clock))),
      loader_(recording) {}

ReadResult ReplayRgbdSource::read(RgbdFrame& frame, std::chrono::milliseconds timeout) {
  const ReadResult r =
      deliver(playback_.next(timeout), recording_->rgbd(), loader_, frame, last_error_);
  if (r == ReadResult::Frame && playback_.options().stamp)
    draw_capture_stamp(frame.colour, frame.timestamp_ns);
  return r;
}

std::string ReplayRgbdSource::name() const {
  return "replay:" + recording_->dir().string();
}

ReplayFisheyeSource::ReplayFisheyeSource(std::shared_ptr<const Recording> recording,
                                         PlaybackOptions options,
                                         std::shared_ptr<PlaybackClock> clock)
    : recording_(recording),
      playback_(make_playback(recording->fisheye(), *recording, options, std::move(clock))),
      loader_(recording) {}

ReadResult ReplayFisheyeSource::read(FisheyeFrame& frame, std::chrono::milliseconds timeout) {
  return deliver(playback_.next(timeout), recording_->fisheye(), loader_, frame, last_error_);
}

std::string ReplayFisheyeSource::name() const {
  return "replay:" + recording_->dir().string() + " (fisheye)";
}

Rig open_replay_rig(const std::filesystem::path& dir, const PlaybackOptions& options) {
  const std::shared_ptr<const Recording> recording = Recording::open(dir);
  auto clock = std::make_shared<PlaybackClock>(recording->start_ns());
  Rig rig;
  rig.calibration = recording->calibration();
  rig.rgbd = std::make_unique<ReplayRgbdSource>(recording, options, clock);
  if (!recording->fisheye().empty()) {
    rig.fisheye = std::make_unique<ReplayFisheyeSource>(recording, options, clock);
  }
  return rig;
}

}  // namespace probeless::replay
