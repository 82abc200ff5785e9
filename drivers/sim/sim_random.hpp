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

inline std::uint64_t hash_combine(std::uint64_t a, std::uint64_t b) {
  return mix64(a ^ mix64(b));
}

// Uniform in [0, 1) from the top 24 bits.
inline float uniform01(std::uint64_t bits) {
  return static_cast<float>(bits >> 40) * (1.0f / 16777216.0f);
}

// A 32-bit bijection with good avalanche (C. Wellons' "lowbias32"): cheap enough per pixel
// and channel, and it vectorises.
inline std::uint32_t hash32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

// Sensor noise with zero mean and unit variance from 20 random bits: the sum of two 10-bit
// uniforms (triangular), scaled. The camera noise models promise mean and variance, not
// shape (docs/sim.md).
inline float unit_noise(std::uint32_t bits) {
  const auto a = static_cast<float>(static_cast<std::int32_t>(bits & 1023u));
  const auto b = static_cast<float>(static_cast<std::int32_t>((bits >> 10) & 1023u));
  return ((a + b + 1.0f) * (1.0f / 1024.0f) - 1.0f) * 2.449489743f;
}

// noise[i] for i in [0, n): the deviates of stream `key` at counters first + i.
inline void fill_unit_noise(float* noise, int n, std::uint32_t key, std::uint32_t first) {
  for (int i = 0; i < n; ++i)
    noise[i] = unit_noise(hash32((first + static_cast<std::uint32_t>(i)) ^ key));
}

}  // namespace probeless::sim
