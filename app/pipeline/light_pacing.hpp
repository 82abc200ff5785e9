#pragma once
// Which fisheye frames the light thread updates its keyframe from: at most `[light] update_hz`
// frames a second, taken in whole bracket cycles (L, M, H, M) so that every exposure level
// still reaches the texels. Every other frame skipped one by one would take only L and H, or
// only the two M's, of a four-frame cycle at a 2:1 ratio.
//
// Why a cap at all: the keyframe update is the largest single cost of a frame in `bench
// pipeline` (the envmap kernel and the light thread together ~45 % of PoCL's CPU with the
// fisheye at 50 frames/s, 2026-11-27), and the light it keeps changes at the pace of lamps and
// of the rig's movement, which the Kalman texels smooth over many frames anyway
// (docs/light-capture.md "Update rate", measured with `eval render`).
#include <algorithm>
#include <cstdint>

#include "core/exposure.hpp"
#include "core/time.hpp"

namespace probeless {

class LightPacing {
 public:
  static constexpr double kCycleFrames = 4;  // BracketSequencer's L, M, H, M
  // 0: every frame.
  explicit LightPacing(double update_hz) : rate_hz_(update_hz) {}

  // Whether the frame with this exposure and time is one the light should update from. A
  // credit of frames accrues at rate_hz over the frames' own time (up to two units of burst,
  // so that a camera at 30 frames/s under a 25 Hz cap gives 25, not 15); a unit, a bracket
  // cycle or a single unbracketed frame, is taken when the credit covers it (5 % slack for
  // timestamps' jitter), and all of a taken cycle's frames with it.
  bool admit(const ExposureStamp& e, TimestampNs t) {
    const bool take = decide(e, t);
    if (!take) ++skipped_;
    return take;
  }
  std::uint64_t skipped() const { return skipped_; }  // frames passed over so far

 private:
  bool decide(const ExposureStamp& e, TimestampNs t) {
    if (rate_hz_ <= 0) return true;
    const bool bracketed = e.level != BracketLevel::Fixed;
    if (bracketed && in_cycle_ && cycle_ == e.cycle) return taken_;
    const double cost = bracketed ? kCycleFrames : 1;
    if (started_)
      credit_ = std::min(credit_ + static_cast<double>(t - last_ns_) * 1e-9 * rate_hz_, 2 * cost);
    else
      credit_ = cost;  // the first unit is always taken
    started_ = true;
    last_ns_ = t;
    taken_ = credit_ >= cost * 0.95;
    if (taken_) credit_ -= cost;
    in_cycle_ = bracketed;
    cycle_ = e.cycle;
    return taken_;
  }

  double rate_hz_;
  double credit_ = 0;
  // Plain values beside flags rather than std::optional: GCC 12 warns (-Wmaybe-uninitialized)
  // on optionals of integers copied out here.
  bool started_ = false, in_cycle_ = false;
  TimestampNs last_ns_ = 0;
  std::uint64_t cycle_ = 0;
  bool taken_ = true;
  std::uint64_t skipped_ = 0;
};

}  // namespace probeless
