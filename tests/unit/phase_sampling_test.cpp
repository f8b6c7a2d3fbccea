// Chi-square tests of every phase function's sampling against its evaluation (Mitsuba 3's
// practice), and the invariants of the scaled phase function (Eq. 8, downsampling paper):
// it integrates to the albedo sum_j W_j, and sample() weights are eval / pdf.
#include "libvdbappear/math/henyey_greenstein.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/math/tabulated_phase.h"
#include "libvdbappear/medium/scattering_function.h"

#include "support/chi2_test.h"
#include "support/test_random.h"

#include <gtest/gtest.h>

#include <string>

namespace vdbappear {
namespace {

test::Chi2Options optionsAbout(const Vec3& axis, int test_count, std::uint64_t seed) {
  test::Chi2Options o;
  o.bins.frame = Frame::fromNormal(axis);
  o.test_count = test_count;
  o.seed = seed;
  return o;
}

TEST(HenyeyGreenstein, SamplesFollowThePhaseFunction) {
  test::TestRandom random(3);
  const std::vector<double> gs{0.0, 0.3, -0.5, 0.8, 0.95, -0.9};
  for (double g : gs) {
    const Vec3 wi = random.direction();
    const test::Chi2Result r = test::chi2TestDirections(
        [&](const Point2& u) { return sampleHenyeyGreenstein(wi, g, u).wo; },
        [&](const Vec3& wo) { return henyeyGreensteinPhase(wi, wo, g); }, optionsAbout(-wi, int(gs.size()), 10 + int(10 * g)));
    EXPECT_TRUE(r.passed) << "g = " << g << ": " << r.summary;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3) << "g = " << g;
  }
}

TEST(HenyeyGreenstein, ForwardScatteringForPositiveG) {
  // mu = -wi . wo: with g > 0, wo continues the propagation direction -wi.
  const Vec3 wi(0, 0, 1);
  EXPECT_GT(henyeyGreensteinPhase(wi, Vec3(0, 0, -1), 0.7), henyeyGreensteinPhase(wi, Vec3(0, 0, 1), 0.7));
  test::TestRandom random(5);
  double mean_mu = 0;
  for (int i = 0; i < 200000; ++i) mean_mu += -wi.dot(sampleHenyeyGreenstein(wi, 0.7, random.point2()).wo);
  EXPECT_NEAR(mean_mu / 200000, 0.7, 0.005);  // <mu> = g
}

TEST(HenyeyGreenstein, RejectsASlightlyWrongSampler) {
  const Vec3 wi = Vec3(0.2, 0.5, -0.8).normalized();
  const test::Chi2Result r = test::chi2TestDirections(
      [&](const Point2& u) { return sampleHenyeyGreenstein(wi, 0.63, u).wo; },
      [&](const Vec3& wo) { return henyeyGreensteinPhase(wi, wo, 0.6); }, optionsAbout(-wi, 1, 7));
  EXPECT_FALSE(r.passed) << r.summary;
}

std::vector<double> randomTable(int bins, std::uint64_t seed) {
  test::TestRandom random(seed);
  std::vector<double> f(bins);
  for (double& v : f) v = random.uniform() < 0.2 ? 0.0 : random.uniform();  // empty bins too
  return f;
}

TEST(TabulatedPhase, NormalisesAndSamplesTheTable) {
  const TabulatedPhase table(randomTable(36, 9));
  double integral = 0;
  for (int b = 0; b < table.bins(); ++b) integral += table.eval(-1 + (2.0 * b + 1) / table.bins()) * 2 * kPi * 2 / table.bins();
  EXPECT_NEAR(integral, 1.0, 1e-12);
  const Vec3 wi = Vec3(0.3, -0.4, 0.5).normalized();
  test::Chi2Options o = optionsAbout(-wi, 1, 21);
  o.bins.theta_cells = 36;  // bin edges in mu coincide with the table's
  const test::Chi2Result r = test::chi2TestDirections([&](const Point2& u) { return table.sample(wi, u).wo; },
                                                      [&](const Vec3& wo) { return table.phase(wi, wo); }, o);
  EXPECT_TRUE(r.passed) << r.summary;
  EXPECT_NEAR(r.pdf_integral, 1.0, 1e-6);
}

TEST(TabulatedPhase, RefusesAnEmptyTable) {
  EXPECT_THROW(TabulatedPhase(std::vector<double>(10, 0.0)), std::invalid_argument);
  EXPECT_THROW(TabulatedPhase(std::vector<double>{}), std::invalid_argument);
}

// A multi-lobe scaled phase function with random SGGX lobes and RGB weights.
ScatteringFunction randomLobes(test::TestRandom& random, int lobes) {
  ScatteringFunction f;
  PhaseLobe lobe;
  lobe.kind = PhaseKind::kSggx;
  for (int j = 0; j < lobes; ++j) {
    lobe.sggx = Sggx(random.spd(0.01));
    f.addLobe(lobe, Rgb(random.uniform(), random.uniform(), random.uniform()) / lobes);
  }
  return f;
}

TEST(ScatteringFunction, MultiLobeSamplingFollowsItsPdf) {
  test::TestRandom random(17);
  for (int lobes : {1, 2, 3}) {
    const ScatteringFunction f = randomLobes(random, lobes);
    const Vec3 wi = random.direction();
    RandomStream picks(5, {lobes});
    const test::Chi2Result r = test::chi2TestDirections(
        [&](const Point2& u) { return f.sample(wi, picks.uniform(), u).wo; },
        [&](const Vec3& wo) { return f.pdf(wi, wo); }, optionsAbout(wi, 3, 30 + lobes));
    EXPECT_TRUE(r.passed) << lobes << " lobes: " << r.summary;
    EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3);
  }
}

TEST(ScatteringFunction, IntegratesToTheAlbedoAndWeightsAreEvalOverPdf) {
  test::TestRandom random(23);
  const ScatteringFunction f = randomLobes(random, 3);
  const Vec3 wi = random.direction();
  for (int c = 0; c < 3; ++c) {
    const double integral = test::integrateSphere([&](const Vec3& wo) { return f.eval(wi, wo)[c]; },
                                                  test::SphereGrid{Frame::fromNormal(wi), 64, 128});
    EXPECT_NEAR(integral, f.albedo()[c], 3e-3 * f.albedo()[c]) << "channel " << c;
  }
  RandomStream rng(1, {2});
  for (int i = 0; i < 1000; ++i) {
    const ScatterSample s = f.sample(wi, rng.uniform(), rng.uniform2());
    if (!(s.pdf > 0)) continue;
    const Rgb expected = f.eval(wi, s.wo) / f.pdf(wi, s.wo);
    EXPECT_LT((s.weight - expected).abs().maxCoeff(), 1e-9 * (1 + expected.abs().maxCoeff()));
  }
}

// A mixture of every kind, HG with |g| < 1e-5 among them, whose sample() weight is not 1 (uniform
// pdf): the sampled lobe's phase value comes with its sample as weight * pdf (scattering_function.cpp).
TEST(ScatteringFunction, MixedKindWeightsAreEvalOverPdf) {
  test::TestRandom random(37);
  const TabulatedPhase table(randomTable(90, 4));
  ScatteringFunction f;
  PhaseLobe lobe;
  f.addLobe(lobe, Rgb(0.1, 0.2, 0.1));  // isotropic
  lobe.kind = PhaseKind::kHenyeyGreenstein;
  lobe.g = 4e-6;
  f.addLobe(lobe, Rgb(0.2, 0.1, 0.1));
  lobe.g = 0.7;
  f.addLobe(lobe, Rgb(0.1, 0.1, 0.3));
  lobe.kind = PhaseKind::kTabulated;
  lobe.table = &table;
  f.addLobe(lobe, Rgb(0.2, 0.2, 0.2));
  lobe.kind = PhaseKind::kSggx;
  lobe.sggx = Sggx(random.spd(0.01));
  f.addLobe(lobe, Rgb(0.3, 0.1, 0.2));
  const Vec3 wi = random.direction();
  RandomStream rng(3, {1});
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const ScatterSample s = f.sample(wi, rng.uniform(), rng.uniform2());
    if (!(s.pdf > 0)) continue;
    ++checked;
    EXPECT_NEAR(s.pdf, f.pdf(wi, s.wo), 1e-9 * s.pdf);
    const Rgb expected = f.eval(wi, s.wo) / f.pdf(wi, s.wo);
    EXPECT_LT((s.weight - expected).abs().maxCoeff(), 1e-9 * (1 + expected.abs().maxCoeff()));
  }
  EXPECT_GT(checked, 1900);
}

TEST(ScatteringFunction, SingleLobeKindsSampleTheirOwnPdf) {
  test::TestRandom random(29);
  const TabulatedPhase table(randomTable(90, 4));
  std::vector<PhaseLobe> kinds(3);
  kinds[0].kind = PhaseKind::kIsotropic;
  kinds[1].kind = PhaseKind::kHenyeyGreenstein;
  kinds[1].g = -0.4;
  kinds[2].kind = PhaseKind::kTabulated;
  kinds[2].table = &table;
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    ScatteringFunction f;
    f.addLobe(kinds[k], Rgb(0.3, 0.6, 0.9));
    const Vec3 wi = random.direction();
    RandomStream picks(5, {int(k)});
    const test::Chi2Result r = test::chi2TestDirections(
        [&](const Point2& u) { return f.sample(wi, picks.uniform(), u).wo; },
        [&](const Vec3& wo) { return f.pdf(wi, wo); }, optionsAbout(-wi, int(kinds.size()), 40 + k));
    EXPECT_TRUE(r.passed) << "kind " << k << ": " << r.summary;
    const ScatterSample s = f.sample(wi, 0.5, Point2(0.3, 0.7));
    EXPECT_LT((s.weight - Rgb(0.3, 0.6, 0.9)).abs().maxCoeff(), 1e-12);  // f / pdf = albedo
  }
}

// A function cleared for reuse (one per path in the path tracer) has no lobes and no cluster, and a
// lobe appended to it is isotropic until set, whatever the slot held before; it then evaluates as
// a fresh function with the same lobes does.
TEST(ScatteringFunction, ClearedFunctionIsRefilledLikeAFreshOne) {
  test::TestRandom random(41);
  const TabulatedPhase table(randomTable(90, 4));
  ScatteringFunction reused;
  PhaseLobe hg;
  hg.kind = PhaseKind::kHenyeyGreenstein;
  hg.g = 0.8;
  reused.addLobe(hg, Rgb(0.5, 0.5, 0.5), 0);
  PhaseLobe tabulated;
  tabulated.kind = PhaseKind::kTabulated;
  tabulated.table = &table;
  reused.addLobe(tabulated, Rgb(0.2, 0.3, 0.4), 1);
  reused.setCluster(3);
  reused.clear();
  EXPECT_EQ(reused.lobeCount(), 0);
  EXPECT_EQ(reused.cluster(), -1);
  const PhaseLobe& first = reused.appendLobe(Rgb(0.4, 0.5, 0.6), 2);
  EXPECT_EQ(first.kind, PhaseKind::kIsotropic);
  EXPECT_EQ(first.g, 0);
  EXPECT_EQ(reused.appendLobe(Rgb(0.1, 0.1, 0.1)).table, nullptr);
  EXPECT_EQ(reused.lobe(1).kind, PhaseKind::kIsotropic);  // the slot that was tabulated
  ScatteringFunction fresh;
  fresh.appendLobe(Rgb(0.4, 0.5, 0.6), 2);
  fresh.appendLobe(Rgb(0.1, 0.1, 0.1));
  for (int i = 0; i < 20; ++i) {
    const Vec3 wi = random.direction(), wo = random.direction();
    EXPECT_EQ(reused.eval(wi, wo).matrix(), fresh.eval(wi, wo).matrix());
    EXPECT_EQ(reused.pdf(wi, wo), fresh.pdf(wi, wo));
  }
  EXPECT_EQ(reused.slot(0), 2);
}

}  // namespace
}  // namespace vdbappear
