// The similarity relations (similarity paper): Legendre moments, Theorem 1, the QP of Eq. (31),
// Algorithm 1, the colour rule and the g quantisation.
#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/henyey_greenstein.h"
#include "libvdbappear/similarity/altered_coefficients.h"
#include "libvdbappear/similarity/altered_phase_qp.h"
#include "libvdbappear/similarity/g_quantiser.h"
#include "libvdbappear/similarity/legendre_moments.h"
#include "libvdbappear/similarity/moment_existence.h"
#include "libvdbappear/similarity/order_distance.h"
#include "libvdbappear/similarity/similarity_relation.h"

#include <Eigen/Dense>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <libalglib/optimization.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace vdbappear;

namespace {

// Eq. (8) by adaptive quadrature.
double numericalMoment(const std::function<double(double)>& f, int n) {
  auto integrand = [&](double t) { return 2 * kPi * f(t) * legendrePolynomials(n, t)[n]; };
  return boost::math::quadrature::gauss_kronrod<double, 61>::integrate(integrand, -1.0, 1.0, 15, 1e-13);
}

TEST(LegendreMoments, HenyeyGreensteinMomentsArePowersOfG) {
  for (double g : {-0.6, 0.0, 0.3, 0.9}) {
    const std::vector<double> f = henyeyGreensteinMoments(g, 6);
    for (int n = 0; n <= 6; ++n)
      EXPECT_NEAR(f[n], numericalMoment([g](double t) { return henyeyGreenstein(t, g); }, n), 1e-9) << "g " << g << " n " << n;
  }
}

TEST(LegendreMoments, TableMomentsAreExactForPiecewiseConstantFunctions) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> table(12);
  for (double& f : table) f = u(rng);
  table = normalisedTable(table);
  auto f = [&](double t) { return table[std::min(11, int((t + 1) / 2 * 12))]; };
  const std::vector<double> moments = tableMoments(table, 5);
  EXPECT_NEAR(moments[0], 1.0, 1e-12);
  for (int n = 1; n <= 5; ++n) {
    double sum = 0;  // integrate bin by bin (the integrand jumps at the edges)
    for (int b = 0; b < 12; ++b) {
      auto piece = [&](double t) { return 2 * kPi * table[b] * legendrePolynomials(n, t)[n]; };
      sum += boost::math::quadrature::gauss_kronrod<double, 15>::integrate(piece, -1 + 2.0 * b / 12, -1 + 2.0 * (b + 1) / 12);
    }
    EXPECT_NEAR(moments[n], sum, 1e-12) << n;
  }
}

TEST(LegendreMoments, MonomialMomentsOfHenyeyGreenstein) {
  const double g = 0.7;
  const std::vector<double> gamma = monomialMoments(henyeyGreensteinMoments(g, 5));
  for (int n = 0; n <= 5; ++n) {
    auto integrand = [&](double t) { return 2 * kPi * henyeyGreenstein(t, g) * std::pow(t, n); };
    const double expected = boost::math::quadrature::gauss_kronrod<double, 61>::integrate(integrand, -1.0, 1.0, 15, 1e-13);
    EXPECT_NEAR(gamma[n], expected, 1e-10) << n;
  }
}

// Eq. (33): 0.9 HG(0.95) + 0.1 vMF(-75), bin averages on `bins` bins, exact.
std::vector<double> gkioulekasTable(int bins) {
  const std::vector<double> hg = tabulateHenyeyGreenstein(0.95, bins);
  const double kappa = -75;
  std::vector<double> table(bins);
  for (int b = 0; b < bins; ++b) {
    const double lo = -1 + 2.0 * b / bins, hi = -1 + 2.0 * (b + 1) / bins;
    const double vmf = kappa / (4 * kPi * std::sinh(kappa)) * (std::exp(kappa * hi) - std::exp(kappa * lo)) / kappa / (hi - lo);
    table[b] = 0.9 * hg[b] + 0.1 * vmf;
  }
  return table;
}

// Random moment sequences: Eq. (23) of random HG and alpha, and perturbed moments of random
// mixtures of HG lobes (many outside the moment space).
std::vector<std::vector<double>> randomMomentSequences(int count, int order, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::vector<double>> sequences;
  for (int i = 0; i < count; ++i) {
    if (i % 2 == 0) {
      const double g = -0.5 + 1.49 * u(rng);
      const double alpha = minimumAlpha(g) + (1 - minimumAlpha(g)) * u(rng);
      sequences.push_back(alteredMoments(henyeyGreensteinMoments(g, order), alpha));
    } else {
      std::vector<double> f(order + 1, 0.0);
      double total = 0;
      for (int lobe = 0; lobe < 3; ++lobe) {
        const double w = u(rng), g = -0.9 + 1.8 * u(rng);
        total += w;
        const std::vector<double> m = henyeyGreensteinMoments(g, order);
        for (int n = 0; n <= order; ++n) f[n] += w * m[n];
      }
      for (int n = 0; n <= order; ++n) f[n] /= total;
      for (int n = 1; n <= order; ++n) f[n] += 0.1 * (u(rng) - 0.5);
      sequences.push_back(f);
    }
  }
  return sequences;
}

// Near the boundary of the moment space: (1 - lambda) (point masses) + lambda (uniform), with
// lambda of either sign; point masses alone lie on the boundary when there are few of them.
std::vector<std::vector<double>> boundaryMomentSequences(int count, int order, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::vector<double>> sequences;
  for (int i = 0; i < count; ++i) {
    std::vector<double> f(order + 1, 0.0);
    const int atoms = 1 + order / 2;
    for (int a = 0; a < atoms; ++a) {
      const std::vector<double> p = legendrePolynomials(order, -1 + 2 * u(rng));
      for (int n = 0; n <= order; ++n) f[n] += p[n] / atoms;
    }
    const double lambda = (i % 2 ? 1 : -1) * std::pow(10.0, -3 + 2 * u(rng));
    for (int n = 1; n <= order; ++n) f[n] *= 1 - lambda;
    sequences.push_back(f);
  }
  return sequences;
}


}  // namespace

TEST(MomentExistence, HenyeyGreensteinMomentsExistAtEveryOrder) {
  for (double g : {-0.8, 0.0, 0.5, 0.95})
    for (int order = 1; order <= 8; ++order) {
      const MomentExistence e = checkMomentsExist(henyeyGreensteinMoments(g, order));
      EXPECT_TRUE(e.exists) << "g " << g << " order " << order;
      EXPECT_GT(e.margin, 0) << "g " << g << " order " << order;
    }
}

// A point mass at t0 has f_n = P_n(t0): on the boundary of the moment space from order 2 on. Scaling
// the moments n >= 1 by 1 - lambda mixes in the uniform distribution (lambda > 0, inside) or leaves
// the space (lambda < 0).
TEST(MomentExistence, PointMassesLieOnTheBoundary) {
  for (int order = 2; order <= 6; ++order) {
    const std::vector<double> atom = legendrePolynomials(order, 0.3);
    EXPECT_NEAR(checkMomentsExist(atom).margin, 0.0, 1e-10) << order;
    for (double lambda : {1e-3, -1e-3}) {
      std::vector<double> f = atom;
      for (int n = 1; n <= order; ++n) f[n] *= 1 - lambda;
      EXPECT_EQ(checkMomentsExist(f).exists, lambda > 0) << "order " << order << " lambda " << lambda;
    }
  }
}

// Theorem 1 against the QP of Eq. (31) on 1000 random sequences (half near the boundary): the QP
// finds a table exactly when the theorem says one exists, wherever |margin| >= 1e-5.
TEST(MomentExistence, AgreesWithQpFeasibilityOnRandomMoments) {
  int checked = 0, infeasible = 0, near_boundary = 0;
  for (int order = 1; order <= 5; ++order) {
    auto sequences = randomMomentSequences(100, order, 7 + order);
    for (auto& f : boundaryMomentSequences(100, order, 70 + order)) sequences.push_back(f);
    for (const auto& f : sequences) {
      const MomentExistence e = checkMomentsExist(f);
      if (std::abs(e.margin) < 1e-5) {
        ++near_boundary;
        continue;
      }
      const PhaseTableSolution qp = solveAlteredPhaseTable(f, 360);
      EXPECT_EQ(qp.feasible, e.exists) << "order " << order << " margin " << e.margin << " QP code " << qp.termination;
      ++checked;
      infeasible += !e.exists;
    }
  }
  EXPECT_GE(checked, 990);
  EXPECT_GE(infeasible, 150) << "the sample must include sequences outside the moment space";
  EXPECT_LE(near_boundary, 10);
}

TEST(AlteredPhaseQp, ReportsMomentsOutsideTheMomentSpace) {
  EXPECT_FALSE(solveAlteredPhaseTable({1.0, 0.5, -0.9}, 360).feasible);  // f_2 < -1/2 is impossible with f_1 = 0.5
  EXPECT_FALSE(solveAlteredPhaseTable({1.0, 1.2}, 360).feasible);
}

// The acceptance test of the table: moments f_0* .. f_N* to 1e-5 (they hold to rounding), non-negative,
// normalised, for HG inputs over g and alpha and for tabulated inputs.
TEST(AlteredPhase, TableHasTheAlteredMomentsAndIsANormalisedPhaseFunction) {
  std::vector<PhaseMoments> inputs;
  for (double g : {0.3, 0.6, 0.8, 0.9, 0.95, 0.99}) inputs.push_back(henyeyGreensteinPhaseMoments(g, 5));
  inputs.push_back(tablePhaseMoments(gkioulekasTable(3600), 5));
  inputs.push_back(tablePhaseMoments(tabulateHenyeyGreenstein(-0.4, 200), 5));
  int cases = 0;
  for (const PhaseMoments& phase : inputs)
    for (double alpha : {0.0, 0.5, 0.8, 1.0}) {
      if (alpha > 0 && alpha < minimumAlpha(phase.moments[1]) + 0.01) continue;
      SimilarityOptions options;
      options.alpha = alpha;
      const AlteredPhase a = computeAlteredPhase(phase, options);
      ASSERT_EQ(int(a.table.size()), 360);
      const std::vector<double> expected = alteredMoments(phase.moments, a.alpha);
      const std::vector<double> got = tableMoments(a.table, a.order);
      for (int n = 0; n <= a.order; ++n) EXPECT_NEAR(got[n], expected[n], 1e-5) << "f1 " << phase.moments[1] << " alpha " << a.alpha << " n " << n;
      double integral = 0;
      for (double f : a.table) {
        EXPECT_GE(f, 0.0);
        integral += 2 * kPi * f * 2.0 / 360;
      }
      EXPECT_NEAR(integral, 1.0, 1e-12);
      ++cases;
    }
  EXPECT_EQ(cases, 31);
}

// Eq. (20): with alpha = 1 - f_1, order 1 gives sigma_s* = sigma_s (1 - f_1) and an isotropic f*.
TEST(AlteredPhase, OrderOneReproducesTheReducedScattering) {
  for (double g : {0.5, 0.9}) {
    SimilarityOptions options;
    options.alpha = 1 - g;
    options.max_order = 1;
    const AlteredPhase a = computeAlteredPhase(henyeyGreensteinPhaseMoments(g, 1), options);
    EXPECT_EQ(a.order, 1);
    EXPECT_NEAR(a.moments[1], 0.0, 1e-15);
    for (double f : a.table) EXPECT_NEAR(f, 1 / (4 * kPi), 1e-9) << "g " << g;
  }
}

TEST(AlteredPhase, DefaultAlphaFollowsSection72) {
  EXPECT_DOUBLE_EQ(defaultAlpha(0.95), 0.3);
  EXPECT_DOUBLE_EQ(defaultAlpha(0.6), 0.4);
  EXPECT_DOUBLE_EQ(defaultAlpha(-0.3), 1.0);
  EXPECT_EQ(computeAlteredPhase(henyeyGreensteinPhaseMoments(0.6, 5), {}).alpha, 0.4);
}

// Algorithm 1's order rule as printed (--order-rule support; the default is the distance rule).
SimilarityOptions supportRule(double alpha = 0) {
  SimilarityOptions options;
  options.alpha = alpha;
  options.order_rule = OrderRule::kSupport;
  return options;
}

// §7.3 exercised: for HG(0.9) at alpha 0.3, Theorem 1 allows order 5, but the order-5 and order-4
// tables are narrow (support 0.23 and 0.58 < 0.65), so Algorithm 1 steps down to order 3.
TEST(AlteredPhase, OverfittingRuleRejectsNarrowTables) {
  const AlteredPhase a = computeAlteredPhase(henyeyGreensteinPhaseMoments(0.9, 5), supportRule());
  EXPECT_EQ(a.existence_margins.size(), 5u);
  for (double margin : a.existence_margins) EXPECT_GT(margin, 0);
  EXPECT_EQ(a.order, 3);
  ASSERT_EQ(a.rejected.size(), 2u);
  EXPECT_EQ(a.rejected[0].order, 5);
  EXPECT_EQ(a.rejected[1].order, 4);
  for (const RejectedOrder& r : a.rejected) EXPECT_LT(r.support, 0.65);
  EXPECT_GE(a.support, 0.65);
  EXPECT_FALSE(a.support_below_threshold);

  SimilarityOptions no_threshold = supportRule();
  no_threshold.support_ratio = 0;
  EXPECT_EQ(computeAlteredPhase(henyeyGreensteinPhaseMoments(0.9, 5), no_threshold).order, 5);
}

// Where Theorem 1 stops: HG(0.8) at alpha 0.3 has no order-3 altered phase function. Algorithm 1
// takes the highest order left; the distance rule searches no higher either.
TEST(AlteredPhase, OrderStopsWhereTheoremOneFails) {
  const AlteredPhase a = computeAlteredPhase(henyeyGreensteinPhaseMoments(0.8, 5), supportRule(0.3));
  ASSERT_EQ(a.existence_margins.size(), 3u);
  EXPECT_LT(a.existence_margins[2], 0);
  EXPECT_EQ(a.order, 2);
  SimilarityOptions distance;
  distance.alpha = 0.3;
  const AlteredPhase d = computeAlteredPhase(henyeyGreensteinPhaseMoments(0.8, 5), distance);
  EXPECT_EQ(d.existence_margins.size(), 3u);
  EXPECT_LE(d.order, 2);
  for (const RejectedOrder& r : d.rejected) EXPECT_LE(r.order, 2);
}

// When every order overfits, the widest table is kept (HG(0.95) at alpha 0.5: supports 0.21 .. 0.30).
TEST(AlteredPhase, KeepsTheWidestTableWhenEveryOrderOverfits) {
  const AlteredPhase a = computeAlteredPhase(henyeyGreensteinPhaseMoments(0.95, 5), supportRule(0.5));
  EXPECT_TRUE(a.support_below_threshold);
  EXPECT_EQ(a.order, 5);
  for (const RejectedOrder& r : a.rejected) {
    EXPECT_NE(r.order, a.order);
    EXPECT_LE(r.support, a.support);
  }
  EXPECT_EQ(a.rejected.size(), 4u);
}

TEST(AlteredPhase, RefusesAlphaBelowTheOrderOneLimit) {
  EXPECT_THROW(computeAlteredPhase(henyeyGreensteinPhaseMoments(0.9, 5), SimilarityOptions{0.04}), std::invalid_argument);
  EXPECT_NO_THROW(computeAlteredPhase(henyeyGreensteinPhaseMoments(0.9, 5), SimilarityOptions{0.06}));
  EXPECT_THROW(computeAlteredPhase(henyeyGreensteinPhaseMoments(0.9, 3), {}), std::invalid_argument) << "too few moments";
}

// A finely tabulated HG gives (nearly) the same result as HG itself.
TEST(AlteredPhase, TabulatedInputAgreesWithTheAnalyticOne) {
  const AlteredPhase analytic = computeAlteredPhase(henyeyGreensteinPhaseMoments(0.85, 5), {});
  const AlteredPhase tabulated = computeAlteredPhase(tablePhaseMoments(tabulateHenyeyGreenstein(0.85, 4096), 5), {});
  EXPECT_NEAR(tabulated.alpha, analytic.alpha, 1e-4);
  EXPECT_EQ(tabulated.order, analytic.order);
  for (std::size_t b = 0; b < analytic.table.size(); ++b) EXPECT_NEAR(tabulated.table[b], analytic.table[b], 1e-3) << b;
}

TEST(AlteredCoefficients, GreyAlbedoKeepsAbsorptionAndScalesScatteringByAlpha) {
  for (double albedo : {0.2, 0.9, 0.999, 1.0}) {
    const double density = 7, alpha = 0.3;
    const AlteredCoefficients c = alterCoefficients(density, Rgb::Constant(albedo), alpha, 0.9);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(c.density * (1 - c.albedo[k]), density * (1 - albedo), 1e-12) << "sigma_a* = sigma_a";
      EXPECT_NEAR(c.density * c.albedo[k], alpha * density * albedo, 1e-12) << "sigma_s* = alpha sigma_s";
    }
    EXPECT_NEAR(c.reduced_attenuation_error, 0.0, 1e-12);
  }
}

// RGB: absorption exact per channel; the reference albedo minimises the worst relative error of
// sigma_tr,1 (checked against a scan), and that error is what alterCoefficients reports. The blue
// channel (0.6 < 0.99 * 0.7) bounds the reference.
TEST(AlteredCoefficients, RgbKeepsAbsorptionAndMinimisesTheWorstChannelError) {
  const Rgb albedo(0.99, 0.9, 0.6);
  const double density = 3, alpha = 0.3, f1 = 0.9;
  const AlteredCoefficients c = alterCoefficients(density, albedo, alpha, f1);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c.density * (1 - c.albedo[k]), density * (1 - albedo[k]), 1e-12) << k;
  const double f1_altered = 1 - (1 - f1) / alpha;
  auto worst = [&](double a_ref) {
    const double r = 1 - a_ref * (1 - alpha);
    const Rgb altered = (1 - (1 - albedo) / r).max(0.0);
    return ((r * (1 - altered * f1_altered) - (1 - albedo * f1)).abs() / (1 - albedo * f1)).maxCoeff();
  };
  double best = 1e300;  // over the references that need no negative scattering
  for (double x = 0.6; x * (1 - alpha) <= albedo.minCoeff(); x += 1e-5) best = std::min(best, worst(x));
  EXPECT_NEAR(c.reduced_attenuation_error, worst(referenceAlbedo(albedo, f1, alpha)), 1e-12);
  EXPECT_LE(c.reduced_attenuation_error, best + 1e-6);
  EXPECT_GT(c.reduced_attenuation_error, 0.01) << "a strongly coloured albedo cannot be exact";
}

TEST(GQuantiser, EveryMomentMovesByAtMostTheTolerance) {
  for (double tolerance : {1e-2, 1e-3, 1e-4}) {
    const GQuantiser q(tolerance, 5);
    EXPECT_GT(q.value(0), -1);
    EXPECT_LT(q.value(q.levels() - 1), 1);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.9999, 0.9999);
    double worst = 0;
    for (int i = 0; i < 100000; ++i) {
      const double g = u(rng), gq = q.value(q.level(g));
      for (int n = 1; n <= 5; ++n) worst = std::max(worst, std::abs(std::pow(g, n) - std::pow(gq, n)));
    }
    EXPECT_LE(worst, tolerance) << tolerance;
    EXPECT_GT(worst, 0.5 * tolerance) << "the levels should not be much finer than needed";
  }
}

namespace {

// What every table of Eq. (31) is checked against, built here from the paper's definitions rather
// than taken from the solver: x = 4 pi c (isotropic x = 1), G scaled alike, Q = S^T S.
struct QpProblem {
  Eigen::MatrixXd g;       // (N+1) x k
  Eigen::MatrixXd q;       // k x k
  Eigen::VectorXd target;  // f*_0 .. f*_N
};

QpProblem qpProblem(const std::vector<double>& moments, int bins) {
  const int order = int(moments.size()) - 1;
  const std::vector<double> g = binMomentMatrix(bins, order);
  QpProblem p{Eigen::MatrixXd(order + 1, bins), Eigen::MatrixXd::Zero(bins, bins), Eigen::VectorXd(order + 1)};
  for (int n = 0; n <= order; ++n) {
    for (int i = 0; i < bins; ++i) p.g(n, i) = g[std::size_t(n) * bins + i] / (4 * kPi);
    p.target[n] = moments[n];
  }
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(bins - 2, bins);
  for (int r = 0; r + 2 < bins; ++r) s.row(r).segment(r, 3) << -1, 2, -1;
  p.q = s.transpose() * s;
  return p;
}

// The KKT conditions of min x^T Q x, G x = t, x >= 0 at the table's x: primal feasibility,
// stationarity on the positive bins (2 Q x + G^T lambda = 0 there, lambda by least squares) and
// non-negative multipliers mu = 2 Q x + G^T lambda on the zero bins; complementarity holds by
// construction (mu = 0 where x > 0, x = 0 where mu may be positive). Returns the worst violation.
double kktViolation(const QpProblem& p, const std::vector<double>& table) {
  const int bins = int(table.size());
  Eigen::VectorXd x(bins);
  for (int i = 0; i < bins; ++i) x[i] = 4 * kPi * table[i];
  double worst = std::max(0.0, -x.minCoeff());
  worst = std::max(worst, (p.g * x - p.target).cwiseAbs().maxCoeff());
  std::vector<int> positive;
  for (int i = 0; i < bins; ++i)
    if (x[i] > 0) positive.push_back(i);
  const Eigen::VectorXd gradient = 2 * p.q * x;
  Eigen::MatrixXd gt(positive.size(), p.g.rows());
  Eigen::VectorXd rhs(positive.size());
  for (std::size_t r = 0; r < positive.size(); ++r) {
    gt.row(Eigen::Index(r)) = p.g.col(positive[r]).transpose();
    rhs[Eigen::Index(r)] = -gradient[positive[r]];
  }
  const Eigen::VectorXd lambda = gt.colPivHouseholderQr().solve(rhs);
  worst = std::max(worst, (gt * lambda - rhs).cwiseAbs().maxCoeff());
  const Eigen::VectorXd mu = gradient + p.g.transpose() * lambda;
  for (int i = 0; i < bins; ++i)
    if (x[i] == 0) worst = std::max(worst, -mu[i]);
  return worst;
}

// An independent exact solve of Eq. (31): ALGLIB's dense active-set solver (BLEIC), whose bins at
// their bound are exactly 0. Returns the number of positive bins.
int activeSetSupportBins(const QpProblem& p) {
  const int bins = int(p.g.cols()), rows = int(p.g.rows());
  alglib::minqpstate state;
  alglib::minqpcreate(bins, state);
  alglib::real_2d_array a;
  a.setlength(bins, bins);
  for (int i = 0; i < bins; ++i)
    for (int j = 0; j < bins; ++j) a(i, j) = 2 * p.q(i, j);
  alglib::minqpsetquadraticterm(state, a, true);
  alglib::real_2d_array c;
  c.setlength(rows, bins + 1);
  alglib::integer_1d_array types;
  types.setlength(rows);
  for (int n = 0; n < rows; ++n) {
    for (int i = 0; i < bins; ++i) c(n, i) = p.g(n, i);
    c(n, bins) = p.target[n];
    types[n] = 0;
  }
  alglib::minqpsetlc(state, c, types);
  alglib::minqpsetbcall(state, 0.0, alglib::fp_posinf);
  alglib::real_1d_array start;
  start.setlength(bins);
  for (int i = 0; i < bins; ++i) start[i] = 1;
  alglib::minqpsetstartingpoint(state, start);
  alglib::minqpsetalgobleic(state, 0, 0, 1e-13, 0);
  alglib::minqpoptimize(state);
  alglib::real_1d_array x;
  alglib::minqpreport report;
  alglib::minqpresults(state, x, report);
  EXPECT_GT(report.terminationtype, 0);
  int positive = 0;
  for (int i = 0; i < bins; ++i) positive += x[i] > 0;
  return positive;
}

// Mixture C of the Fig. 9 experiment: 0.9 HG(0.8737) + 0.1 HG(-0.3).
std::vector<double> mixtureCMoments(int order) {
  const std::vector<double> a = henyeyGreensteinMoments(0.8737, order), b = henyeyGreensteinMoments(-0.3, order);
  std::vector<double> m(order + 1);
  for (int n = 0; n <= order; ++n) m[n] = 0.9 * a[n] + 0.1 * b[n];
  return m;
}

std::vector<double> firstN(std::vector<double> moments, int order) {
  moments.resize(std::size_t(order) + 1);
  return moments;
}

}  // namespace

// Every table the QP returns is its exact optimum: the KKT conditions hold to 1e-9 for HG inputs,
// Eq. 33 and mixture C at orders 1 to 5, and for random feasible moment sequences.
TEST(AlteredPhaseQp, EveryTableSatisfiesTheKktConditions) {
  std::vector<std::vector<double>> problems;
  const std::vector<double> eq33 = tablePhaseMoments(gkioulekasTable(3600), 5).moments;
  for (int order = 1; order <= 5; ++order) {
    for (double g : {0.5, 0.9, 0.95})
      for (double alpha : {0.3, std::max(0.3, 1 - g)})
        problems.push_back(alteredMoments(henyeyGreensteinMoments(g, order), alpha));
    for (double alpha : {0.3, 1 - eq33[1]}) problems.push_back(alteredMoments(firstN(eq33, order), alpha));
    problems.push_back(alteredMoments(mixtureCMoments(order), 0.3));
  }
  for (auto& f : randomMomentSequences(60, 4, 17)) problems.push_back(f);
  int solved = 0;
  for (const std::vector<double>& f : problems) {
    const PhaseTableSolution s = solveAlteredPhaseTable(f, 360);
    if (!s.feasible) continue;
    EXPECT_LE(kktViolation(qpProblem(f, 360), s.table), 1e-9) << "order " << f.size() - 1 << " f1 " << f[1];
    ++solved;
  }
  EXPECT_GE(solved, 70);  // 73: the infeasible ones lie outside the moment space (Theorem 1)
}

// The supports that decide Algorithm 1 (§7.3) are those of the exact optimum: Eq. 33 at orders 4 and
// 5 (alpha = 1 - f1) and mixture C at order 3 (alpha 0.3) against an independent active-set solve.
TEST(AlteredPhaseQp, SupportsAgreeWithAnIndependentActiveSetSolve) {
  const std::vector<double> eq33 = tablePhaseMoments(gkioulekasTable(3600), 5).moments;
  const std::vector<std::vector<double>> problems = {alteredMoments(firstN(eq33, 4), 1 - eq33[1]),
                                                     alteredMoments(eq33, 1 - eq33[1]),
                                                     alteredMoments(mixtureCMoments(3), 0.3)};
  for (const std::vector<double>& f : problems) {
    const PhaseTableSolution s = solveAlteredPhaseTable(f, 360);
    ASSERT_TRUE(s.feasible);
    const int bins = int(std::count_if(s.table.begin(), s.table.end(), [](double v) { return v > 0; }));
    EXPECT_EQ(bins, activeSetSupportBins(qpProblem(f, 360))) << "order " << f.size() - 1;
    EXPECT_DOUBLE_EQ(tableSupport(s.table), bins / 360.0);
  }
}

// The distance of an order (order_distance.h): zero for the input itself at alpha 1; for an
// isotropic f and an isotropic f* at alpha 0.5, W1 = integral of |F - F/2| = 1/2 (F(mu) = (mu+1)/2);
// the same whatever the two grids' resolutions.
TEST(OrderDistance, MatchesClosedForms) {
  const std::vector<double> isotropic(360, 1 / (4 * kPi)), fine(3600, 1 / (4 * kPi));
  EXPECT_NEAR(similarityDistance(tableCdf(isotropic), isotropic, 1.0), 0.0, 1e-14);
  EXPECT_NEAR(similarityDistance(tableCdf(fine), isotropic, 0.5), 0.5, 1e-12);
  const std::vector<double> hg = tabulateHenyeyGreenstein(0.8, 360);
  EXPECT_NEAR(similarityDistance(tableCdf(hg), hg, 1.0), 0.0, 1e-14);
  EXPECT_GT(similarityDistance(tableCdf(hg), isotropic, 1.0), 0.1);  // negative control: HG(0.8) is not isotropic
}

// The distance rule (issue 27) at alpha 0.3: mixture C, where order 3 renders three times worse than
// order 1 (docs/similarity.md §4), takes order 1; Eq. 33, where order 5 is best and the support rule
// falls back to order 1, takes order 5; HG(0.9) takes order 3, as the support rule does.
TEST(AlteredPhase, DistanceRuleTakesTheClosestOrder) {
  SimilarityOptions options;
  options.alpha = 0.3;
  options.order_rule = OrderRule::kDistance;
  std::vector<double> c_table = tabulateHenyeyGreenstein(0.8737, 3600), back = tabulateHenyeyGreenstein(-0.3, 3600);
  for (std::size_t i = 0; i < c_table.size(); ++i) c_table[i] = 0.9 * c_table[i] + 0.1 * back[i];
  const AlteredPhase c = computeAlteredPhase(tablePhaseMoments(c_table, 5), options);
  EXPECT_EQ(c.order, 1);
  const AlteredPhase eq33 = computeAlteredPhase(tablePhaseMoments(gkioulekasTable(3600), 5), options);
  EXPECT_EQ(eq33.order, 5);
  const AlteredPhase hg = computeAlteredPhase(henyeyGreensteinPhaseMoments(0.9, 5), options);
  EXPECT_EQ(hg.order, 3);
  for (const AlteredPhase* a : {&c, &eq33, &hg})
    for (const RejectedOrder& r : a->rejected)
      if (r.distance > 0) EXPECT_GE(r.distance, a->distance) << "order " << r.order;
  options.order_rule = OrderRule::kSupport;  // control: Algorithm 1 as printed
  EXPECT_EQ(computeAlteredPhase(tablePhaseMoments(c_table, 5), options).order, 3);
  EXPECT_EQ(computeAlteredPhase(tablePhaseMoments(gkioulekasTable(3600), 5), options).order, 1);
}

// A warm start (altered_phase_qp.h) changes the time, not the table: along 60 consecutive g levels of
// the quantiser at its default tolerance (steps of 4e-4 about g = 0.9), every order's table started
// from its neighbour's equals the cold solve (interior point + active set) to rounding, with the
// same support, and the warm path is the one taken (else it saves nothing). A start far from the
// problem (HG(0.3)'s table for Eq. 33) must still give the cold table.
TEST(AlteredPhaseQp, WarmStartsGiveTheColdTable) {
  const GQuantiser quantiser(1e-3, 5);
  for (int order = 1; order <= 5; ++order) {
    std::vector<double> previous;
    int warm = 0, solved = 0;
    for (int level = quantiser.level(0.9) - 30; level < quantiser.level(0.9) + 30; ++level) {
      const double g = quantiser.value(level);
      const std::vector<double> f = alteredMoments(henyeyGreensteinMoments(g, order), defaultAlpha(g));
      const PhaseTableSolution cold = solveAlteredPhaseTable(f, 360);
      const PhaseTableSolution hot = solveAlteredPhaseTable(f, 360, previous.empty() ? nullptr : &previous);
      ASSERT_EQ(hot.feasible, cold.feasible) << "order " << order << " g " << g;
      if (!cold.feasible) continue;
      ++solved;
      warm += hot.warm_started;
      for (int i = 0; i < 360; ++i) ASSERT_NEAR(hot.table[i], cold.table[i], 1e-13) << "order " << order << " g " << g << " bin " << i;
      EXPECT_EQ(tableSupport(hot.table), tableSupport(cold.table)) << "order " << order << " g " << g;
      previous = hot.table;
    }
    EXPECT_GE(solved, 30) << "order " << order;  // order 5 exists (Theorem 1) at 38 of the 60 levels
    EXPECT_GE(warm, solved - 1) << "order " << order;
  }
  const std::vector<double> eq33 = tablePhaseMoments(gkioulekasTable(3600), 5).moments;
  const std::vector<double> far = solveAlteredPhaseTable(alteredMoments(henyeyGreensteinMoments(0.3, 4), 0.7), 360).table;
  for (const std::vector<double>& f : {alteredMoments(firstN(eq33, 4), 1 - eq33[1]), alteredMoments(eq33, 1 - eq33[1])}) {
    const PhaseTableSolution cold = solveAlteredPhaseTable(f, 360), hot = solveAlteredPhaseTable(f, 360, &far);
    ASSERT_TRUE(hot.feasible);
    for (int i = 0; i < 360; ++i) ASSERT_NEAR(hot.table[i], cold.table[i], 1e-13) << "Eq. 33 order " << f.size() - 1 << " bin " << i;
    EXPECT_LE(kktViolation(qpProblem(f, 360), hot.table), 1e-9);
  }
  EXPECT_THROW(solveAlteredPhaseTable(eq33, 360, &eq33), std::invalid_argument);  // a start on other bins
}

// Both order rules choose the same order and table along a run of g levels with warm starts as
// without (similarity_medium.cpp solves whole media so).
TEST(AlteredPhase, WarmStartsChangeNeitherOrderNorTable) {
  const GQuantiser quantiser(1e-3, 5);
  for (OrderRule rule : {OrderRule::kSupport, OrderRule::kDistance}) {
    SimilarityOptions options;
    options.order_rule = rule;
    QpWarmStarts warm;
    for (int level = quantiser.level(0.7); level < quantiser.level(0.96); level += 25) {
      const PhaseMoments phase = henyeyGreensteinPhaseMoments(quantiser.value(level), 5);
      const AlteredPhase cold = computeAlteredPhase(phase, options), hot = computeAlteredPhase(phase, options, &warm);
      ASSERT_EQ(hot.order, cold.order) << orderRuleName(rule) << " g " << quantiser.value(level);
      EXPECT_EQ(hot.rejected.size(), cold.rejected.size());
      for (int i = 0; i < 360; ++i) ASSERT_NEAR(hot.table[i], cold.table[i], 1e-13) << orderRuleName(rule) << " bin " << i;
    }
  }
}
