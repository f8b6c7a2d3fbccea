// Building blocks of the procedural media: the fiber segment index and gradient noise.
#include "libvdbappear/procedural/fiber_segments.h"
#include "libvdbappear/procedural/gradient_noise.h"

#include <gtest/gtest.h>

#include <random>

namespace vdbappear {
namespace {

// The index finds, for every point, exactly the lowest-numbered segment that a brute-force
// search over all segments finds.
TEST(SegmentIndex, AgreesWithBruteForce) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  auto point = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  std::vector<FiberSegment> segments;
  for (int k = 0; k < 300; ++k) segments.push_back({point(), point(), 0.005 + 0.03 * u(rng), k});
  const SegmentIndex index(segments, 0.05);
  int inside = 0;
  for (int k = 0; k < 200000; ++k) {
    const Vec3 p = point() * 1.1 - Vec3::Constant(0.05);
    int expected = -1;
    for (std::size_t s = 0; s < segments.size() && expected < 0; ++s)
      if (insideSegment(segments[s], p)) expected = int(s);
    ASSERT_EQ(index.find(p), expected) << p.transpose();
    inside += expected >= 0;
  }
  EXPECT_GT(inside, 10000) << "the test must hit segments often";
}

TEST(SegmentIndex, CylindersAreFlatEnded) {
  const FiberSegment s{Vec3(0, 0, 0), Vec3(0, 0, 1), 0.1, 0};
  EXPECT_TRUE(insideSegment(s, Vec3(0.09, 0, 0.5)));
  EXPECT_FALSE(insideSegment(s, Vec3(0.11, 0, 0.5)));
  EXPECT_TRUE(insideSegment(s, Vec3(0, 0, 0.999)));
  EXPECT_FALSE(insideSegment(s, Vec3(0, 0, 1.001)));
  EXPECT_FALSE(insideSegment(s, Vec3(0, 0, -0.001)));
}

TEST(GradientNoise, VanishesAtLatticePointsAndIsSmoothAndBounded) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-20, 20);
  for (int k = 0; k < 100; ++k) {
    const Vec3 lattice = Vec3(u(rng), u(rng), u(rng)).array().floor();
    EXPECT_NEAR(gradientNoise(lattice, 1), 0, 1e-12);
  }
  double max_value = 0, max_slope = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double h = 1e-4, value = gradientNoise(p, 3);
    max_value = std::max(max_value, std::abs(value));
    for (int axis = 0; axis < 3; ++axis)
      max_slope = std::max(max_slope, std::abs(gradientNoise(p + h * Vec3::Unit(axis), 3) - value) / h);
    EXPECT_EQ(value, gradientNoise(p, 3)) << "deterministic";
  }
  EXPECT_LE(max_value, 1.0);
  EXPECT_GT(max_value, 0.3) << "not degenerate";
  EXPECT_LT(max_slope, 4.0) << "no jumps: the slope of gradient noise is bounded";
  EXPECT_NE(gradientNoise(Vec3(0.3, 0.4, 0.5), 1), gradientNoise(Vec3(0.3, 0.4, 0.5), 2)) << "the seed matters";
}

TEST(GradientNoise, FractalSumStaysInRange) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-5, 5);
  for (int k = 0; k < 5000; ++k) {
    const double v = fractalNoise(Vec3(u(rng), u(rng), u(rng)), 7, 5);
    EXPECT_LE(std::abs(v), 1.0);
  }
}

}  // namespace
}  // namespace vdbappear
