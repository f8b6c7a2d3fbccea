#pragma once
// A stream of uniform random numbers for one path: SplitMix64 (Steele, Lea, Flood 2014) seeded
// by hashing (seed, pixel, sample), so every path draws the same numbers whatever the thread
// that traces it: renders are deterministic under --seed for any thread count.

#include "libvdbappear/math/vector.h"
#include "libvdbappear/util/hash_random.h"

#include <cstdint>
#include <initializer_list>

namespace vdbappear {

class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::initializer_list<std::int64_t> keys) : state_(hashKeys(seed, keys)) {}

  double uniform() {  // in [0,1)
    state_ += 0x9e3779b97f4a7c15ull;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }
  Point2 uniform2() {
    const double a = uniform();
    return {a, uniform()};
  }

 private:
  std::uint64_t state_;
};

}  // namespace vdbappear
