#pragma once
// 64-bit FNV-1a: stable across runs, builds and machines (unlike std::hash), so it can name
// cache files and checksum them. Cache file names and checksums on disk depend on its exact
// output: it must not change (tests/unit/base/hash_test.cpp pins it).
#include <cstdint>
#include <string_view>

namespace probeless {

inline constexpr std::uint64_t kFnv1a64Seed = 0xcbf29ce484222325ULL;

// `seed` chains calls: fnv1a64(b, fnv1a64(a)) == fnv1a64(a + b).
constexpr std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t seed = kFnv1a64Seed) {
  std::uint64_t h = seed;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

}  // namespace probeless
