#pragma once
// Sources that replay a recording (docs/formats.md "Recording format"). Frames come back as
// they were recorded: sequence, timestamp, pixels, exposure stamp and truth (unless looping
// or rebasing shifts sequence and time, see PlaybackOptions).
//
// The fisheye replays the exposures that were taken: set_next_exposure() is accepted and
// ignored, so a bracket sequencer fed by a replay sees its decisions have no effect.
#include <filesystem>
#include <memory>
#include <string>

#include "drivers/replay/playback.hpp"
#include "drivers/replay/recording.hpp"
#include "drivers/source.hpp"

namespace probeless::replay {

class ReplayRgbdSource final : public RgbdSource {
 public:
  ReplayRgbdSource(std::shared_ptr<const Recording> recording, PlaybackOptions options,
                   std::shared_ptr<PlaybackClock> clock = nullptr);
  // A frame whose image cannot be read gives Error (last_error() names the file); the next
  // read() goes on with the following frame.
  ReadResult read(RgbdFrame& frame, std::chrono::milliseconds timeout) override;
  SourceState state() const override { return playback_.state(); }
  std::string last_error() const override { return last_error_; }
  std::string name() const override;

 private:
  std::shared_ptr<const Recording> recording_;
  Playback playback_;
  FrameLoader loader_;
  std::string last_error_;
};

class ReplayFisheyeSource final : public FisheyeSource {
 public:
  ReplayFisheyeSource(std::shared_ptr<const Recording> recording, PlaybackOptions options,
                      std::shared_ptr<PlaybackClock> clock = nullptr);
  ReadResult read(FisheyeFrame& frame, std::chrono::milliseconds timeout) override;
  SourceState state() const override { return playback_.state(); }
  std::string last_error() const override { return last_error_; }
  std::string name() const override;
  void set_next_exposure(const ExposureStamp&) override {}  // replays what was taken

 private:
  std::shared_ptr<const Recording> recording_;
  Playback playback_;
  FrameLoader loader_;
  std::string last_error_;
};

// Both streams of a recording with one shared clock, and its calibration. The fisheye is null
// when the recording has no fisheye frames. Throws ParseError for a malformed recording.
Rig open_replay_rig(const std::filesystem::path& dir, const PlaybackOptions& options);

}  // namespace probeless::replay
