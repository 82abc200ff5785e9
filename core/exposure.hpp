#pragma once
// Exposure of a linear camera: E = gain * time, gain given in dB (thesis ch. 5;
// ../shared/DESIGN.md "Bracketing"). One stop is a factor of 2 in E.
#include <cmath>
#include <cstdint>

namespace probeless {

struct Exposure {
  double time_s = 0.01;  // integration time
  double gain_db = 0.0;  // analogue gain, 20 log10(g)

  double gain() const { return std::pow(10.0, gain_db / 20.0); }
  double value() const { return time_s * gain(); }  // E
  bool operator==(const Exposure&) const = default;
};

inline double gain_db_from_linear(double g) { return 20.0 * std::log10(g); }

// Position in the L, M, H, M bracket cycle (thesis ch. 5). Fixed = not bracketing.
enum class BracketLevel : std::uint8_t { Low, Medium, High, Fixed };

inline const char* to_string(BracketLevel level) {
  switch (level) {
    case BracketLevel::Low: return "low";
    case BracketLevel::Medium: return "medium";
    case BracketLevel::High: return "high";
    case BracketLevel::Fixed: return "fixed";
  }
  return "?";
}

// The exposure a fisheye frame was actually taken with, and where it sits in the cycle.
struct ExposureStamp {
  Exposure exposure;
  BracketLevel level = BracketLevel::Fixed;
  std::uint32_t cycle_position = 0;  // 0..3 within L, M, H, M
  std::uint64_t cycle = 0;           // count of completed cycles
  bool operator==(const ExposureStamp&) const = default;
};

}  // namespace probeless
