#pragma once
// The Source seam (../shared/DESIGN.md "Seams"): a device or a recording that delivers
// timestamped frames and reports a typed state. read() never blocks longer than the timeout
// it is given (callers pass about one frame period). "No frame yet" and "end of stream" are
// different answers.
#include <Eigen/Core>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "core/calibration.hpp"
#include "core/exposure.hpp"
#include "core/frame.hpp"
#include "core/room_box.hpp"

namespace probeless {

enum class SourceState { Streaming, NoDevice, NoSignal, Stalled, Ended };

const char* to_string(SourceState s);

enum class ReadResult { Frame, NoFrameYet, EndOfStream, Error };

template <typename FrameT>
class Source {
 public:
  virtual ~Source() = default;
  // Fills `frame` and returns Frame, or says why not. Error: state() and last_error() say more.
  virtual ReadResult read(FrameT& frame, std::chrono::milliseconds timeout) = 0;
  virtual SourceState state() const = 0;
  virtual std::string last_error() const { return {}; }
  virtual std::string name() const = 0;  // for status and logs ("sim", "replay:/path", ...)
};

using RgbdSource = Source<RgbdFrame>;

// The fisheye additionally takes the exposure for the next frame (the bracket sequencer's
// decision); it stamps each frame with the exposure actually used.
class FisheyeSource : public Source<FisheyeFrame> {
 public:
  virtual void set_next_exposure(const ExposureStamp& exposure) = 0;
};

// What a rig knows of the scene it looks at, in its world frame. The synthetic rig knows
// both; a camera or a recording knows neither, and the configuration says instead.
struct RigScene {
  std::optional<Eigen::Vector3d> object_anchor;  // where virtual objects stand by default
  std::optional<RoomBox> room;  // the room the fisheye sees, for light-capture parallax
};

// A rig as a source set: what `--source sim` or `--source replay:DIR` opens.
struct Rig {
  std::unique_ptr<RgbdSource> rgbd;
  std::unique_ptr<FisheyeSource> fisheye;  // may be null (a TUM sequence has none)
  RigCalibration calibration;
  RigScene scene;
};

}  // namespace probeless
