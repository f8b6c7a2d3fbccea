#pragma once
// Random inputs for tests, from a seeded engine.

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/random_spd.h"
#include "libvdbappear/math/vector.h"

#include <cmath>
#include <random>

namespace vdbappear::test {

class TestRandom {
 public:
  explicit TestRandom(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return std::uniform_real_distribution<double>(0.0, 1.0)(engine_); }
  Point2 point2() { return Point2(uniform(), uniform()); }
  Vec3 direction() {
    const double z = 1 - 2 * uniform(), phi = 2 * kPi * uniform();
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
  }
  // R diag(lambda) R^T, eigenvalues log-uniform in [min_eigenvalue, 1].
  Mat3 spd(double min_eigenvalue) {
    return randomSpdMatrix(uniform(), uniform(), uniform(), Vec3(uniform(), uniform(), uniform()), min_eigenvalue);
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace vdbappear::test
