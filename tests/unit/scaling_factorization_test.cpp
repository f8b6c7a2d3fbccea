// The factorised scaling function of Eq. (4.21)-(4.24) in the displacement chapter
// (libvdbappear/prefilter/scaling_factorization.h, scaling_tables.h): the concentric map's
// round trip and equal areas, the tables' interpolation, and Appendix B.2's consistency: a separable
// R is reproduced by T S; a non-separable one is not (the negative control). Deterministic under the
// seed whatever the thread count.
#include "libvdbappear/math/concentric_mapping.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/math/sampling.h"
#include "libvdbappear/prefilter/scaling_factorization.h"

#include "support/test_random.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cmath>
#include <vector>

namespace vdbappear {
namespace {

TEST(ConcentricMapping, RoundTripsAndKeepsAreas) {
  test::TestRandom random(5);
  for (int k = 0; k < 1000; ++k) {
    const double a = random.uniform(), b = random.uniform();
    const Point2 u(a, b);
    const Vec3 w = squareToHemisphere(u);
    EXPECT_NEAR(w.norm(), 1, 1e-12);
    EXPECT_GE(w.z(), 0);
    EXPECT_LT((hemisphereToSquare(w) - u).norm(), 1e-12) << u.transpose();
  }
  // Equal areas: a regular grid of the square is uniform on the hemisphere, where E[cos] = 1/2 and
  // E[cos^2] = 1/3; the cosine-weighted map of math/sampling.h (the negative control) gives 2/3.
  double z = 0, z2 = 0, z_cosine = 0;
  const int n = 400;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Point2 u((i + 0.5) / n, (j + 0.5) / n);
      const double c = squareToHemisphere(u).z();
      z += c;
      z2 += c * c;
      z_cosine += sampleCosineHemisphere(u).z();
    }
  EXPECT_NEAR(z / (n * n), 0.5, 1e-4);
  EXPECT_NEAR(z2 / (n * n), 1.0 / 3, 1e-4);
  EXPECT_NEAR(z_cosine / (n * n), 2.0 / 3, 1e-3);
}

TEST(ScalingTables, InterpolateBetweenBinCentres) {
  AngularScaling S;
  S.resolution = 5;
  S.values.resize(625);
  for (std::size_t k = 0; k < S.values.size(); ++k) S.values[k] = Rgb(double(k), 1.0, -double(k));
  for (int ib = 0; ib < 5; ++ib)
    for (int ia = 0; ia < 5; ++ia) {
      const Vec3 wi = S.binDirection(ia, ib), wo = S.binDirection(4 - ia, ib / 2);
      EXPECT_LT((S(wi, wo) - S.values[S.index(ia, ib, 4 - ia, ib / 2)]).abs().maxCoeff(), 1e-9);
    }
  // T linear in x between the first and last bin centres is reproduced; beyond them it is clamped.
  SpatialScaling T;
  T.resolution = 4;
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) T.values.push_back(Rgb::Constant(1 + a + 10 * b));
  EXPECT_NEAR(T(Point2(0.5, 0.375))[0], 1 + 1.5 + 10 * 1, 1e-12);
  EXPECT_NEAR(T(Point2(0.01, 0.99))[0], 1 + 0 + 10 * 3, 1e-12);
}

// A smooth spatial factor over 16 x 16 coarse cells (resolved by 4 x 4 bins) and a smooth positive angular one.
double spatialFactor(int u, int v) { return 1 + 0.4 * std::sin(u * 0.15) * std::cos(v * 0.1); }
double angularFactor(const Vec3& wi, const Vec3& wo) { return 0.6 + 0.4 * wi.z() * wo.z() + 0.2 * wi.x() * wo.x() + 0.1 * wo.y(); }

// RMS of T S / R - 1 over random cells and direction pairs within the table's 75 degrees.
double relativeRmsError(const FactorizedScaling& factors, const ScalingSampler& R) {
  test::TestRandom random(9);
  double sum = 0;
  const int count = 4000;
  for (int k = 0; k < count; ++k) {
    const int u = std::min(15, int(16 * random.uniform())), v = std::min(15, int(16 * random.uniform()));
    const double ua = random.uniform(), ub = random.uniform(), oa = random.uniform(), ob = random.uniform();
    const Vec3 wi = limitPolarAngle(sampleCosineHemisphere(Point2(ua, ub)), 75 * kPi / 180);
    const Vec3 wo = limitPolarAngle(sampleCosineHemisphere(Point2(oa, ob)), 75 * kPi / 180);
    const ScalingSample sample = R(u, v, 0, wi, wo);
    const double r = sample.original[0] / sample.prefiltered[0], approx = factors(Point2((u + 0.5) / 16, (v + 0.5) / 16), wi, wo)[0];
    sum += (approx / r - 1) * (approx / r - 1);
  }
  return std::sqrt(sum / count);
}

FactorizationSettings smallTables() {
  FactorizationSettings s;
  s.spatial_resolution = 4;
  s.angular_resolution = 9;
  s.pairs_per_spatial_bin = 2000;
  return s;
}

// Appendix B.2: for R = t(x) s(wi, wo), T averages one and follows t, and T S = R up to the
// sampling of the positions and the angular table's interpolation.
TEST(ScalingFactorization, SeparableScalingIsReproduced) {
  const ScalingSampler R = [](int u, int v, std::uint64_t, const Vec3& wi, const Vec3& wo) {
    return ScalingSample{Rgb::Constant(spatialFactor(u, v) * angularFactor(wi, wo)), Rgb::Ones()};
  };
  const FactorizedScaling factors = factorizeScaling(R, 16, 16, smallTables());
  double mean = 0, t_mean = 0;
  for (const Rgb& t : factors.T.values) mean += t[0] / 16;
  for (int v = 0; v < 16; ++v)
    for (int u = 0; u < 16; ++u) t_mean += spatialFactor(u, v) / 256;
  EXPECT_NEAR(mean, 1, 1e-12);
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) {
      double t = 0;
      for (int v = 4 * b; v < 4 * b + 4; ++v)
        for (int u = 4 * a; u < 4 * a + 4; ++u) t += spatialFactor(u, v) / 16;
      EXPECT_NEAR(factors.T.values[a + 4 * b][0], t / t_mean, 0.02) << a << " " << b;
    }
  // Measured: 0.025, from the 16 positions per S bin and T's bilinear reading between its 4 x 4 bins.
  EXPECT_LT(relativeRmsError(factors, R), 0.035);
}

// A spatial variation that changes with the light's direction is not rank one: the factorisation
// cannot follow it (the chapter's Fig. 4.6 measures how small this part is for real surfaces).
TEST(ScalingFactorization, NonSeparableScalingIsNot) {
  const ScalingSampler R = [](int u, int v, std::uint64_t, const Vec3& wi, const Vec3& wo) {
    return ScalingSample{Rgb::Constant(angularFactor(wi, wo) + 0.5 * std::sin(u * 0.4 + v * 0.1) * wi.x()), Rgb::Ones()};
  };
  // Measured: 0.25.
  EXPECT_GT(relativeRmsError(factorizeScaling(R, 16, 16, smallTables()), R), 0.15);
}

// Where the prefiltered model reflects nothing of the original's light (here: light beyond 60
// degrees), S stops at max_scaling; where neither reflects, footnote 2's epsilon makes it 1.
TEST(ScalingFactorization, BinsTheModelCannotCarryAreCapped) {
  const ScalingSampler R = [](int, int, std::uint64_t, const Vec3& wi, const Vec3&) {
    const bool grazing = wi.z() < 0.5;
    return ScalingSample{Rgb(1, 0, 1), grazing ? Rgb(0, 0, 0) : Rgb(0.5, 0, 0.5)};
  };
  FactorizationSettings s = smallTables();
  s.angular_resolution = 5;
  s.pairs_per_spatial_bin = 100;
  const FactorizedScaling factors = factorizeScaling(R, 4, 4, s);
  for (int ib = 0; ib < 5; ++ib)
    for (int ia = 0; ia < 5; ++ia) {
      const Rgb value = factors.S.values[factors.S.index(ia, ib, 2, 2)];
      const bool grazing = factors.S.binDirection(ia, ib).z() < 0.5;
      EXPECT_NEAR(value[0], grazing ? 20 : 2, 1e-5) << ia << ", " << ib;
      EXPECT_NEAR(value[1], 1, 1e-12);
    }
}

// A ratio of sums over n positions is biased by O(1/n) (docs/displacement.md §9): with the same
// light everywhere and a prefiltered reflectance that varies from cell to cell without spatial order
// (0.1 + u^3, u uniform, CV^2 = 0.66), 16 positions per bin make the plain S about 4% too bright
// on average over its 10^4 bins; the jackknife removes that, to its O(1/n^2) and the bins' noise.
TEST(ScalingFactorization, JackknifeRemovesTheBiasOfFewPositions) {
  constexpr int kCells = 64;
  std::vector<double> prefiltered(kCells * kCells);  // cell (u, v) at u + kCells v
  test::TestRandom random(17);
  double sum = 0;
  for (double& p : prefiltered) sum += p = 0.1 + std::pow(random.uniform(), 3);
  const double exact = kCells * kCells / sum;  // the map-wide ratio
  const ScalingSampler R = [&](int u, int v, std::uint64_t, const Vec3&, const Vec3&) {
    return ScalingSample{Rgb::Ones(), Rgb::Constant(prefiltered[std::size_t(u + kCells * v)])};
  };
  FactorizationSettings s = smallTables();
  s.angular_resolution = 10;
  s.pairs_per_spatial_bin = 10;
  s.positions_per_angular_bin = 16;
  const auto meanOfS = [&](bool jackknife) {
    s.jackknife = jackknife;
    const FactorizedScaling factors = factorizeScaling(R, kCells, kCells, s);
    double mean = 0;
    for (const Rgb& value : factors.S.values) mean += value[0] / double(factors.S.values.size());
    return mean / exact - 1;
  };
  // Measured: plain +0.0418, jackknife -0.0045.
  EXPECT_GT(meanOfS(false), 0.025);
  EXPECT_LT(std::abs(meanOfS(true)), 0.01);
}

// Each S bin's relative standard error (FactorizedScaling::S_relative_errors) is what its draw
// spreads by: with a direction-free R every bin estimates the same map-wide ratio from its own
// positions, so the bins' spread about their mean is the error each should report. Where the
// original is the prefiltered model's light times 2 exactly, every bin is exact and reports 0 (the
// negative control: an error from the samples' spread alone would not be).
TEST(ScalingFactorization, EachBinReportsTheSpreadOfItsDraw) {
  constexpr int kCells = 64;
  std::vector<double> prefiltered(kCells * kCells);
  test::TestRandom random(23);
  for (double& p : prefiltered) p = 0.1 + std::pow(random.uniform(), 3);
  FactorizationSettings s = smallTables();
  s.angular_resolution = 10;
  s.pairs_per_spatial_bin = 10;
  s.positions_per_angular_bin = 64;
  // The original's light: 1 in every cell (the ratio varies from cell to cell), or twice the model's.
  const auto tables = [&](bool twice_the_model) {
    const ScalingSampler R = [&, twice_the_model](int u, int v, std::uint64_t, const Vec3&, const Vec3&) {
      const double m = prefiltered[std::size_t(u + kCells * v)];
      return ScalingSample{Rgb::Constant(twice_the_model ? 2 * m : 1.0), Rgb::Constant(m)};
    };
    return factorizeScaling(R, kCells, kCells, s);
  };
  const FactorizedScaling noisy = tables(false);
  ASSERT_EQ(noisy.S_relative_errors.size(), noisy.S.values.size());
  double mean = 0, reported = 0;
  for (std::size_t k = 0; k < noisy.S.values.size(); ++k) {
    mean += noisy.S.values[k][0];
    reported += noisy.S_relative_errors[k];
  }
  mean /= double(noisy.S.values.size());
  reported /= double(noisy.S.values.size());
  double spread = 0;
  for (const Rgb& value : noisy.S.values) spread += (value[0] / mean - 1) * (value[0] / mean - 1);
  spread = std::sqrt(spread / double(noisy.S.values.size()));
  // Measured: spread 0.1023, reported 0.1018.
  std::printf("S's bins: spread %.4f about their mean, reported %.4f on average\n", spread, reported);
  EXPECT_GT(spread, 0.03);
  EXPECT_NEAR(reported / spread, 1, 0.1) << reported << " " << spread;
  const FactorizedScaling exact = tables(true);
  for (std::size_t k = 0; k < exact.S.values.size(); ++k) {
    EXPECT_NEAR(exact.S.values[k][0], 2, 1e-5);
    EXPECT_LT(exact.S_relative_errors[k], 1e-6);
  }
}

// Each position of each bin draws its own estimate (the sampler's `visit`): where the strata are the
// coarse cells (1024 positions over 32^2 cells, a map at 32x) every bin meets cell k at its k-th
// position, and with the visit k alone every bin drew the same estimates there: all bins came out
// alike, off together by their shared draw. Here each estimate's noise is keyed by its visit, and
// the bins spread about the true ratio (1) by the error they report, their mean within a few of
// its standard errors.
TEST(ScalingFactorization, BinsDrawIndependentEstimates) {
  constexpr int kCells = 32;
  const ScalingSampler R = [](int u, int v, std::uint64_t visit, const Vec3&, const Vec3&) {
    RandomStream noise(visit, {u, v});
    return ScalingSample{Rgb::Constant(0.5 + noise.uniform()), Rgb::Ones()};
  };
  FactorizationSettings s = smallTables();
  s.angular_resolution = 6;
  s.pairs_per_spatial_bin = 10;
  s.positions_per_angular_bin = kCells * kCells;
  const FactorizedScaling tables = factorizeScaling(R, kCells, kCells, s);
  double mean = 0, reported = 0, spread = 0;
  const double bins = double(tables.S.values.size());
  for (std::size_t k = 0; k < tables.S.values.size(); ++k) {
    mean += tables.S.values[k][0] / bins;
    reported += tables.S_relative_errors[k] / bins;
  }
  for (const Rgb& value : tables.S.values) spread += (value[0] - mean) * (value[0] - mean) / bins;
  spread = std::sqrt(spread);
  // Measured: spread 0.0091, reported 0.0090, mean 0.99982 (a uniform's 1 / sqrt(12 * 1024) is 0.0090).
  std::printf("S's bins of one draw each: spread %.4f, reported %.4f, mean %.5f\n", spread, reported, mean);
  EXPECT_NEAR(spread / reported, 1, 0.1);
  EXPECT_NEAR(mean, 1, 4 * reported / std::sqrt(bins));
}

// With shared positions every wi bin of one wo reads the same cells: a direction-free R gives one
// value per wo bin (the wi bins move together), unshared each bin its own. The per-view sampler is
// called once per position and wo, with every wi at once; a separable R is reproduced as unshared
// (to 2.5% RMS).
TEST(ScalingFactorization, SharedPositionsServeEveryLightDirectionOfAView) {
  constexpr int kCells = 16;
  const ScalingSampler varying = [](int u, int v, std::uint64_t, const Vec3&, const Vec3&) {
    return ScalingSample{Rgb::Ones(), Rgb::Constant(0.1 + 0.05 * ((u * 7 + v * 3) % 11))};
  };
  FactorizationSettings s = smallTables();
  s.positions_per_angular_bin = 4;
  const auto spread_along_wi = [&](bool shared) {
    s.shared_positions = shared;
    const FactorizedScaling f = factorizeScaling(varying, kCells, kCells, s);
    double largest = 0;
    for (int ob = 0; ob < s.angular_resolution; ++ob)
      for (int oa = 0; oa < s.angular_resolution; ++oa)
        for (int ib = 0; ib < s.angular_resolution; ++ib)
          for (int ia = 0; ia < s.angular_resolution; ++ia)
            largest = std::max(largest, std::abs(f.S.values[f.S.index(ia, ib, oa, ob)][0] -
                                                 f.S.values[f.S.index(0, 0, oa, ob)][0]));
    return largest;
  };
  EXPECT_EQ(spread_along_wi(true), 0);
  EXPECT_GT(spread_along_wi(false), 0.1);

  std::atomic<int> calls{0};
  std::atomic<std::size_t> lights{0};
  const ViewScalingSampler per_view = [&](int u, int v, std::uint64_t visit, const std::vector<Vec3>& wis, const Vec3& wo,
                                            ScalingSample* out) {
    ++calls;
    lights += wis.size();
    sampledPerLight(varying)(u, v, visit, wis, wo, out);
  };
  s.shared_positions = true;
  factorizeScaling(varying, kCells, kCells, s, nullptr, per_view);
  const int N = s.angular_resolution;
  EXPECT_EQ(calls.load(), N * N * s.positions_per_angular_bin);
  EXPECT_EQ(lights.load(), std::size_t(N) * N * N * N * s.positions_per_angular_bin);

  const ScalingSampler separable = [](int u, int v, std::uint64_t, const Vec3& wi, const Vec3& wo) {
    return ScalingSample{Rgb::Constant(spatialFactor(u, v) * angularFactor(wi, wo)), Rgb::Ones()};
  };
  FactorizationSettings shared = smallTables();
  shared.shared_positions = true;
  const double error = relativeRmsError(factorizeScaling(separable, 16, 16, shared), separable);
  std::printf("separable R with shared positions: %.4f RMS\n", error);
  EXPECT_LT(error, 0.035);
}

// S's positions are stratified one per stratum whatever their count: with the original reflecting
// only in the map's last row (or column) of 8 cells, a bin is exactly that row's share of the
// positions, 1/8. A grid of round(sqrt(n))^2 strata visited n times (before) leaves strata out
// where n is not a square: at 8192 positions 89 of 91^2, nearly the whole last row of strata.
TEST(ScalingFactorization, EveryStratumOfSHoldsOnePositionAtAnyCount) {
  for (const int count : {64, 512, 1024, 8192})  // 8 x 8, 16 x 32, 32 x 32, 64 x 128 strata
    for (const bool shared : {false, true})
      for (const bool along_v : {false, true}) {
        const int cells_x = along_v ? 1 : 8, cells_y = along_v ? 8 : 1;
        const ScalingSampler lastRow = [&](int u, int v, std::uint64_t, const Vec3&, const Vec3&) {
          const bool last = along_v ? v == cells_y - 1 : u == cells_x - 1;
          return ScalingSample{Rgb::Constant(last ? 1.0 : 0.0), Rgb::Ones()};
        };
        FactorizationSettings s = smallTables();
        s.angular_resolution = 1;
        s.pairs_per_spatial_bin = 1;
        s.positions_per_angular_bin = count;
        s.shared_positions = shared;
        s.epsilon = 0;
        const FactorizedScaling f = factorizeScaling(lastRow, cells_x, cells_y, s);
        EXPECT_DOUBLE_EQ(f.S.values[0][0], 0.125) << count << " positions, shared " << shared << ", along v " << along_v;
      }
}

TEST(ScalingFactorization, SameTablesOnOneThreadAndMany) {
  const ScalingSampler R = [](int u, int v, std::uint64_t, const Vec3& wi, const Vec3& wo) {
    return ScalingSample{Rgb(spatialFactor(u, v), angularFactor(wi, wo), spatialFactor(v, u) * angularFactor(wo, wi)),
                         Rgb(1, 0.5, 2)};
  };
  FactorizationSettings s = smallTables();
  s.angular_resolution = 5;
  s.pairs_per_spatial_bin = 100;
  const FactorizedScaling many = factorizeScaling(R, 16, 16, s);
  FactorizedScaling one;
  tbb::task_arena(1).execute([&] { one = factorizeScaling(R, 16, 16, s); });
  for (std::size_t k = 0; k < many.T.values.size(); ++k) EXPECT_TRUE((many.T.values[k] == one.T.values[k]).all());
  for (std::size_t k = 0; k < many.S.values.size(); ++k) EXPECT_TRUE((many.S.values[k] == one.S.values[k]).all());
}

}  // namespace
}  // namespace vdbappear
