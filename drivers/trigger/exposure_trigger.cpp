#include "drivers/trigger/exposure_trigger.hpp"

#include "drivers/bracket/bracket_sequencer.hpp"

namespace probeless {

TimestampNs RecordingTrigger::fire(const ExposureStamp& exposure) {
  const TimestampNs now = monotonic_now_ns();
  std::lock_guard lock(mutex_);
  pulses_.push_back({exposure, now});
  return now;
}

std::vector<TriggerPulse> RecordingTrigger::pulses() const {
  std::lock_guard lock(mutex_);
  return pulses_;
}

ExposureStamp start_next_frame(BracketSequencer& sequencer, FisheyeSource& camera,
                               ExposureTrigger* trigger) {
  const ExposureStamp next = sequencer.next();
  // The exposure first: a triggered sensor latches its registers at the edge.
  camera.set_next_exposure(next);
  if (trigger) trigger->fire(next);
  return next;
}

}  // namespace probeless
