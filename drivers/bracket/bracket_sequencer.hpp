#pragma once
// The bracket sequencer: which exposure the fisheye takes next, in the L, M, H, M cycle, and
// how the low and high exposures follow the scene (thesis ch. 5; docs/bracketing.md). No
// device and no OpenCL here: a camera driver applies next() and feeds observe() with counts
// from the frame (count_exposure on the CPU, or kernels/hdr/exposure_count on the device).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/exposure.hpp"
#include "core/exposure_count.hpp"
#include "core/image.hpp"

namespace probeless {

struct BracketConfig {
  double mains_hz = 50.0;     // time <= one mains period (flicker); <= 0: no mains limit
  double min_time_s = 1e-5;   // the camera's shortest integration
  double max_time_s = 0.1;    // the camera's longest (its frame period)
  double max_gain_db = 24.0;  // the camera's highest analogue gain (0 dB is the lowest)
  // Low: one stop down while more than this fraction of the pixels saturate. The thesis's
  // 0.001 left the sim's window clouds (a few hundred of 262 144 fisheye pixels, ~1e4 against
  // walls of ~1e2) clipped in every frame: unobserved texels that held 75 % of the chrome
  // sphere's error (`eval render`: sphere 0.249 -> 0.131 with 2e-5; docs/bracketing.md).
  double saturated_fraction_threshold = 2e-5;
  // Medium is placed between H and the highest L stop at which at most this fraction
  // saturate (the thesis's L threshold): the bulk of the scene, not its brightest few pixels
  // (following L down took st_fagans' median merge error from 0.6 % to 1.4 %).
  double medium_saturated_fraction = 0.001;
  double zero_fraction_threshold = 0.001;  // high: one stop up above this
  double initial_exposure = 0.005;         // E of the medium level at start (e.g. the camera's AE)
  int initial_spread_stops = 3;            // L and H start this many stops below / above M
  int min_spacing_stops = 1;               // at least one stop between L, M and H (thesis)
  bool adapt_medium = true;                // false: M stays at initial_exposure
  int medium_period_cycles = 2;            // adapted M moves at most one stop per this many cycles
};

// ExposureStats and count_exposure (the CPU counts, and the reference of the OpenCL
// reduction kernels/hdr/exposure_count) live in core/exposure_count.hpp.

// Longest time (up to the mains period and the camera's max), then the lowest gain that
// reaches E; clamped to what the camera can do.
Exposure split_exposure(double exposure_value, const BracketConfig& config);
// The longest integration split_exposure uses: min(max_time_s, 1 / mains_hz).
double max_integration_time(const BracketConfig& config);

class BracketSequencer {
 public:
  explicit BracketSequencer(const BracketConfig& config = {});

  // The exposure for the next frame, with its level, cycle position (0..3 = L, M, H, M) and
  // cycle count; advances the cycle.
  ExposureStamp next();
  // Counts from a frame taken with `taken`. Returns true when an exposure changed. Frames
  // taken at a stop the sequencer has since left (latency) and Fixed frames are ignored.
  bool observe(const ExposureStamp& taken, const ExposureStats& stats);

  // Exposures in stops relative to initial_exposure.
  int low_stop() const { return stop_[0]; }
  int medium_stop() const { return stop_[1]; }
  int high_stop() const { return stop_[2]; }
  int min_stop() const { return min_stop_; }
  int max_stop() const { return max_stop_; }
  // The highest stop known to saturate no more than medium_saturated_fraction (L if none):
  // M moves towards the middle of it and H.
  int bulk_low_stop() const;
  double exposure_value(int stop) const;
  const BracketConfig& config() const { return config_; }

 private:
  int stop_of(const Exposure& e) const;
  // Records the saturated fraction seen at an L stop, kept monotonic in the stop (a longer
  // exposure never saturates fewer pixels).
  void record_low_fraction(int stop, double fraction);

  BracketConfig config_;
  int stop_[3] = {0, 0, 0};  // L, M, H
  int min_stop_ = 0;
  int max_stop_ = 0;
  std::uint64_t frame_ = 0;
  std::int64_t medium_last_move_cycle_ = -1000;  // long ago
  std::vector<double> low_fraction_;             // per stop from min_stop_; < 0: not seen
};

}  // namespace probeless
