// Multi-lobe SGGX fits of one downsampled voxel (§5, §8.1 of the downsampling paper).
#include "libvdbappear/lobes/lobe_fit.h"
#include "libvdbappear/lobes/ndf_quadrature.h"
#include "libvdbappear/math/random_spd.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/math/sggx.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

namespace vdbappear {
namespace {

std::vector<Mat3> randomChildren(int n, std::uint64_t seed) {
  std::vector<Mat3> children;
  for (int k = 0; k < n; ++k) {
    RandomStream rng(seed, {k});
    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
    children.push_back(randomSpdMatrix(u1, u2, u3, Vec3(rng.uniform(), rng.uniform(), rng.uniform()), 0.01));
  }
  return children;
}

// Fibres of roughness 0.1 along x (n_x children) and along y (n_y children).
std::vector<Mat3> twoFibreFamilies(int n_x, int n_y) {
  std::vector<Mat3> children(n_x, Sggx::fiberMatrix(Vec3(1, 0, 0), 0.1));
  children.insert(children.end(), n_y, Sggx::fiberMatrix(Vec3(0, 1, 0), 0.1));
  return children;
}

bool isSpd(const Mat3& S) {
  return isPositiveDefinite(sggxDiagonal(S), sggxOffDiagonal(S)) &&
         (S - S.transpose()).norm() < 1e-12;
}

// Invariants of Eq. (10)-(11): fractions sum to 1, the fraction-weighted lobe S is the children's
// mean S (the count-weighted naive S of Eq. 5), every lobe S is SPD; for every forced m.
TEST(LobeFit, InvariantsOfEquations10And11) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const std::vector<Mat3> children = randomChildren(int(1 + seed * 3), seed);
    Mat3 mean = Mat3::Zero();
    for (const Mat3& S : children) mean += S / double(children.size());
    for (int m = 1; m <= 4; ++m) {
      LobeFitOptions options;
      options.forced_lobes = m;
      const LobeFit fit = fitLobes(children, options, seed);
      ASSERT_GE(fit.lobes.size(), 1u);
      EXPECT_LE(int(fit.lobes.size()), std::min<int>(m, int(children.size())));
      double fraction = 0;
      Mat3 weighted = Mat3::Zero();
      for (const SggxLobe& lobe : fit.lobes) {
        EXPECT_TRUE(isSpd(lobe.S)) << "seed " << seed << " m " << m;
        EXPECT_GT(lobe.fraction, 0);
        fraction += lobe.fraction;
        weighted += lobe.fraction * lobe.S;
      }
      EXPECT_NEAR(fraction, 1.0, 1e-12);
      EXPECT_LT((weighted - mean).norm(), 1e-12 * (1 + mean.norm())) << "seed " << seed << " m " << m;
    }
  }
}

TEST(LobeFit, IdenticalChildrenMakeOneExactLobe) {
  const std::vector<Mat3> children(27, Sggx::fiberMatrix(Vec3(1, 2, 3), 0.2));
  const LobeFit fit = fitLobes(children, LobeFitOptions{}, 7);
  ASSERT_EQ(fit.lobes.size(), 1u);
  EXPECT_DOUBLE_EQ(fit.lobes[0].fraction, 1.0);
  EXPECT_LT((fit.lobes[0].S - children[0]).norm(), 1e-15);
  EXPECT_EQ(fit.error_by_lobes.size(), 1u);  // one distinct S: m = 1 is exact, no larger m is tried
  EXPECT_NEAR(fit.error_by_lobes[0], 0.0, 1e-12);
}

// Two crossing fibre families (warp and weft in one coarse voxel, as in Fig. 4, Example 2): one
// lobe blurs them, two lobes are exact, so the rule of §8.1 picks 2; the fractions are the
// families' shares, and the larger comes first.
TEST(LobeFit, CrossingFibresGetTwoLobes) {
  const std::vector<Mat3> children = twoFibreFamilies(40, 24);
  const LobeFit fit = fitLobes(children, LobeFitOptions{}, 3);
  ASSERT_EQ(fit.lobes.size(), 2u);
  ASSERT_GE(fit.error_by_lobes.size(), 2u);
  EXPECT_GT(fit.error_by_lobes[0], 0.1);
  EXPECT_LT(fit.error_by_lobes[1], 1e-9);
  EXPECT_DOUBLE_EQ(fit.lobes[0].fraction, 40.0 / 64);
  EXPECT_LT((fit.lobes[0].S - children.front()).norm(), 1e-12);
  EXPECT_LT((fit.lobes[1].S - children.back()).norm(), 1e-12);

  LobeFitOptions one;
  one.max_lobes = 1;
  EXPECT_EQ(fitLobes(children, one, 3).lobes.size(), 1u);
}

// The rule stops adding lobes when a lobe does not halve the error: fibres jittered by a few
// degrees around one tangent are one lobe's worth, plus an outlier family that is not.
TEST(LobeFit, LobeCountRuleComparesSuccessiveErrors) {
  std::vector<Mat3> children;
  for (int k = 0; k < 32; ++k) {
    RandomStream rng(11, {k});
    const Vec3 t(0.05 * (rng.uniform() - 0.5), 0.05 * (rng.uniform() - 0.5), 1);
    children.push_back(Sggx::fiberMatrix(t, 0.3));
  }
  LobeFitOptions options;
  const LobeFit fit = fitLobes(children, options, 5);
  ASSERT_EQ(fit.error_by_lobes.size(), 3u);
  // Whatever m it picks, the rule holds for it: each added lobe halved the error, the next would not.
  const std::size_t m = fit.lobes.size();
  for (std::size_t j = 1; j < m; ++j) EXPECT_LE(fit.error_by_lobes[j], 0.5 * fit.error_by_lobes[j - 1]);
  if (m < 3) EXPECT_GT(fit.error_by_lobes[m], 0.5 * fit.error_by_lobes[m - 1]);
  options.keep_ratio = 1.0;  // any improvement adds a lobe
  EXPECT_EQ(fitLobes(children, options, 5).lobes.size(), 3u);
  options.keep_ratio = 0.0;  // only exact fits add a lobe
  EXPECT_EQ(fitLobes(children, options, 5).lobes.size(), 1u);
}

TEST(LobeFit, SameSeedSameFit) {
  const std::vector<Mat3> children = randomChildren(64, 99);
  const LobeFit a = fitLobes(children, LobeFitOptions{}, 4), b = fitLobes(children, LobeFitOptions{}, 4);
  ASSERT_EQ(a.lobes.size(), b.lobes.size());
  for (std::size_t j = 0; j < a.lobes.size(); ++j) {
    EXPECT_EQ(a.lobes[j].fraction, b.lobes[j].fraction);
    EXPECT_EQ(a.lobes[j].S, b.lobes[j].S);
  }
  EXPECT_EQ(a.error_by_lobes, b.error_by_lobes);
}

// The error's quadrature: the L2 distance between two single lobes is symmetric, zero for equal
// lobes, and the fit error of the true mixture is zero.
TEST(LobeFit, ErrorIsADistanceOverTheSphere) {
  const Mat3 a = Sggx::fiberMatrix(Vec3(1, 0, 0), 0.2), b = Sggx::surfaceMatrix(Vec3(0, 0, 1), 0.3);
  const double ab = lobeFitError({{a, 1.0}}, {b}), ba = lobeFitError({{b, 1.0}}, {a});
  EXPECT_GT(ab, 0.1);
  EXPECT_NEAR(ab, ba, 1e-9 * ab);
  EXPECT_NEAR(lobeFitError({{a, 1.0}}, {a}), 0.0, 1e-12);
  EXPECT_NEAR(lobeFitError({{a, 0.25}, {b, 0.75}}, {a, b, b, b}), 0.0, 1e-12);
}

// kNdfQuadraturePoints is enough for the narrowest lobes the procedural media hold (fibres of roughness
// 0.1, ridges about 0.1 rad wide): the error matches a 100x finer quadrature within 2%.
TEST(LobeFit, ErrorQuadratureResolvesRoughness01Fibres) {
  const Mat3 x = Sggx::fiberMatrix(Vec3(1, 0, 0), 0.1), y = Sggx::fiberMatrix(Vec3(0.3, 1, 0.2), 0.1);
  const Sggx fx(x), fy(y);
  const int n = 100 * kNdfQuadraturePoints;
  const double golden_angle = 3.14159265358979323846 * (3 - std::sqrt(5.0));
  double sum = 0;
  for (int k = 0; k < n; ++k) {  // a finer spherical Fibonacci set, whole sphere
    const double z = 1 - 2 * (k + 0.5) / n, r = std::sqrt(1 - z * z);
    const Vec3 m(r * std::cos(golden_angle * k), r * std::sin(golden_angle * k), z);
    const double d = 0.5 * fx.D(m) + 0.5 * fy.D(m) - fx.D(m);
    sum += d * d;
  }
  const double reference = std::sqrt(4 * 3.14159265358979323846 / n * sum);
  EXPECT_NEAR(lobeFitError({{x, 1.0}}, {x, y}), reference, 0.02 * reference);
}

}  // namespace
}  // namespace vdbappear
