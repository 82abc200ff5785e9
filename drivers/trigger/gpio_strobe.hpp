#pragma once
// The optional strobe input beside the exposure trigger (issue #7): a sensor in external-
// trigger mode drives a strobe (flash) output while it integrates; wired to a GPIO input, its
// edges say when each frame's exposure really began. The line is requested for edge events
// through libgpiod 1.6 (the v1 character-device ABI), whose event timestamps the kernel takes
// with ktime_get_ns() in the interrupt handler: CLOCK_MONOTONIC, the clock of TimestampNs, so
// a frame can carry its strobe time instead of the driver's end-of-readout time.
#include <chrono>
#include <gpiod.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "core/frame.hpp"
#include "core/time.hpp"

namespace probeless {

enum class StrobeEdge { Rising, Falling, Both };
// "rising", "falling" or "both"; throws std::invalid_argument naming the text otherwise.
StrobeEdge parse_strobe_edge(std::string_view text);
std::string_view to_string(StrobeEdge edge);

struct GpioStrobeConfig {
  std::string chip;  // name, path (/dev/gpiochip1), label or number, as for the trigger
  unsigned line = 0;
  StrobeEdge edge = StrobeEdge::Rising;  // the exposure start (most sensors' strobe polarity)
  bool active_low = false;               // inverts which physical edge counts as rising
  std::string consumer = "probeless-strobe";
};

struct StrobeEvent {
  TimestampNs time_ns = 0;  // the kernel's CLOCK_MONOTONIC time of the edge
  bool rising = true;       // with StrobeEdge::Both, which one it was
};

class GpioStrobe {
 public:
  // Opens the chip and requests the line for edge events. Throws std::runtime_error naming
  // the chip and line when either is missing, out of range or busy.
  explicit GpioStrobe(GpioStrobeConfig config);
  ~GpioStrobe();
  GpioStrobe(const GpioStrobe&) = delete;
  GpioStrobe& operator=(const GpioStrobe&) = delete;

  // The next edge, waiting at most `timeout` (0: only what is already queued); nullopt when
  // none came. Signals do not cut the wait short. Throws std::runtime_error when the line
  // fails (chip removed).
  std::optional<StrobeEvent> wait(std::chrono::nanoseconds timeout);
  // Drains the queued edges and returns the newest: the strobe of the frame that was just
  // read when one frame at a time is in flight (trigger, read, trigger, ...).
  std::optional<StrobeEvent> latest();

  std::string name() const;  // "CHIP line N", as configured

 private:
  GpioStrobeConfig config_;
  gpiod::chip chip_;
  gpiod::line line_;
};

// Stamps `frame` with its exposure start: the newest queued edge, or when none is queued the
// next one within `timeout`. Returns the edge, or nullopt (the frame keeps its timestamp).
// Assumes one frame in flight, as the pipeline's trigger-read loop has.
std::optional<StrobeEvent> stamp_with_strobe(GpioStrobe& strobe, FisheyeFrame& frame,
                                             std::chrono::nanoseconds timeout);

}  // namespace probeless
