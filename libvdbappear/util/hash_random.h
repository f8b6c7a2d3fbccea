#pragma once
// Counter-based random numbers: a value is a pure function of (seed, keys), so procedural media
// are the same whatever the thread count or the order in which voxels are visited.

#include <cstdint>
#include <initializer_list>

namespace vdbappear {

// SplitMix64 finaliser (Steele, Lea, Flood 2014).
inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

inline std::uint64_t hashKeys(std::uint64_t seed, std::initializer_list<std::int64_t> keys) {
  std::uint64_t h = mix64(seed);
  for (std::int64_t k : keys) h = mix64(h ^ std::uint64_t(k));
  return h;
}

// Uniform in [0,1) from (seed, keys).
inline double hashUniform(std::uint64_t seed, std::initializer_list<std::int64_t> keys) {
  return double(hashKeys(seed, keys) >> 11) * 0x1.0p-53;
}

}  // namespace vdbappear
