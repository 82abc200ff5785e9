#pragma once
// "Fire the next exposure" (issue #5, thesis ch. 5): the bracket sequencer tells the fisheye
// the exposure of its next frame, then a trigger starts that frame. A camera in free-running
// mode needs no trigger; one in external-trigger mode gets a GPIO pulse (gpio_trigger.hpp),
// so every frame is taken at the exposure that was set for it and the L-M-H-M cycle cannot
// slip a frame against the sensor's own timing. RecordingTrigger is the fake beside the real
// line: it keeps every pulse, for tests and for runs without hardware.
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "core/exposure.hpp"
#include "core/time.hpp"
#include "drivers/source.hpp"

namespace probeless {

class BracketSequencer;

struct TriggerPulse {
  ExposureStamp exposure;   // what the frame the pulse starts was set to
  TimestampNs time_ns = 0;  // CLOCK_MONOTONIC at the leading edge
};

class ExposureTrigger {
 public:
  virtual ~ExposureTrigger() = default;
  // Starts one frame, whose exposure `exposure` the camera has already been given. Returns the
  // time of the leading edge. Throws std::runtime_error when the line fails.
  virtual TimestampNs fire(const ExposureStamp& exposure) = 0;
  virtual std::string name() const = 0;
};

// The fake: records each pulse; no device.
class RecordingTrigger final : public ExposureTrigger {
 public:
  TimestampNs fire(const ExposureStamp& exposure) override;
  std::string name() const override { return "recording"; }
  std::vector<TriggerPulse> pulses() const;

 private:
  mutable std::mutex mutex_;
  std::vector<TriggerPulse> pulses_;
};

// One step of the bracket loop before a frame: the sequencer's next exposure goes to the
// camera, then (if there is one) the trigger fires. Returns what the frame will be stamped
// with.
ExposureStamp start_next_frame(BracketSequencer& sequencer, FisheyeSource& camera,
                               ExposureTrigger* trigger);

}  // namespace probeless
