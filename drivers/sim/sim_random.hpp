#pragma once
// Counter-based random numbers for the synthetic rig: every value is a hash of (seed, what,
// where), so a frame is the same whichever thread renders which row, and in any order.
#include <cstdint>

namespace probeless::sim {

// splitmix64's finaliser.
inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

inline std::uint64_t hash_combine(std::uint64_t a, std::uint64_t b) { return mix64(a ^ mix64(b)); }

// Uniform in [0, 1) from the top 24 bits.
inline float uniform01(std::uint64_t bits) {
  return static_cast<float>(bits >> 40) * (1.0f / 16777216.0f);
}

// Sensor noise deviates with zero mean and unit variance from 20 random bits: the sum of
// two 10-bit uniforms (triangular), scaled. Cheap enough for every pixel of every frame; the
// camera noise models promise mean and variance, not shape (docs/sim.md).
inline float unit_noise(std::uint64_t bits20) {
  const auto a = static_cast<float>(bits20 & 1023u), b = static_cast<float>((bits20 >> 10) & 1023u);
  return ((a + b + 1.0f) * (1.0f / 1024.0f) - 1.0f) * 2.449489743f;
}

}  // namespace probeless::sim
