#include "chi2_test.h"

#include "libvdbappear/math/constants.h"

#include <boost/math/distributions/chi_squared.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace vdbappear::test {

namespace {

int binIndex(const Chi2Options& o, const Vec3& w) {
  const Vec3 local = o.bins.frame.toLocal(w);
  const double cos_theta = std::clamp(local.z(), -1.0, 1.0);
  double phi = std::atan2(local.y(), local.x());
  if (phi < 0) phi += 2 * kPi;
  const int i = std::min(o.bins.theta_cells - 1, int((cos_theta + 1) / 2 * o.bins.theta_cells));
  const int j = std::min(o.bins.phi_cells - 1, int(phi / (2 * kPi) * o.bins.phi_cells));
  return i * o.bins.phi_cells + j;
}

std::vector<double> expectedFractions(const SphereFunction& pdf, const Chi2Options& o) {
  const int nt = o.bins.theta_cells * o.cells_per_bin, np = o.bins.phi_cells * o.cells_per_bin;
  std::vector<double> expected(std::size_t(o.bins.theta_cells) * o.bins.phi_cells, 0.0);
  for (int i = 0; i < nt; ++i) {
    const double c0 = -1 + 2.0 * i / nt, c1 = -1 + 2.0 * (i + 1) / nt;
    for (int j = 0; j < np; ++j) {
      const double p0 = 2 * kPi * j / np, p1 = 2 * kPi * (j + 1) / np;
      const int bin = (i / o.cells_per_bin) * o.bins.phi_cells + j / o.cells_per_bin;
      expected[bin] += integrateCell(pdf, o.bins, c0, c1, p0, p1);
    }
  }
  return expected;
}

}  // namespace

Chi2Result chi2TestDirections(const DirectionSampler& sample, const SphereFunction& pdf, const Chi2Options& o) {
  Chi2Result result;
  std::vector<double> observed(std::size_t(o.bins.theta_cells) * o.bins.phi_cells, 0.0);
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::uint64_t invalid = 0;
  for (std::uint64_t k = 0; k < o.sample_count; ++k) {
    // One draw at a time, y first: the order GCC gave the two unsequenced arguments this replaced,
    // so that the sanitizer build (clang, left to right) tests the very samples that GCC's does.
    const double u_y = uniform(rng);
    const double u_x = uniform(rng);
    const Vec3 w = sample(Point2(u_x, u_y));
    if (!w.allFinite() || std::abs(w.norm() - 1) > 1e-6) {
      ++invalid;
      continue;
    }
    observed[binIndex(o, w)] += 1;
  }
  result.invalid_fraction = double(invalid) / double(o.sample_count);

  const std::vector<double> fractions = expectedFractions(pdf, o);
  for (double f : fractions) result.pdf_integral += f;

  // Pearson's statistic; bins expecting < 5 samples are pooled into one.
  double pooled_observed = 0, pooled_expected = 0;
  int used_bins = 0;
  for (std::size_t b = 0; b < observed.size(); ++b) {
    const double expected = fractions[b] * double(o.sample_count);
    if (expected < 5) {
      pooled_observed += observed[b];
      pooled_expected += expected;
      continue;
    }
    result.statistic += (observed[b] - expected) * (observed[b] - expected) / expected;
    ++used_bins;
  }
  if (pooled_expected > 0) {
    result.statistic += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) /
                        std::max(pooled_expected, 1.0);
    ++used_bins;
  }
  result.degrees_of_freedom = std::max(1, used_bins - 1);
  const boost::math::chi_squared distribution(result.degrees_of_freedom);
  result.p_value = boost::math::cdf(boost::math::complement(distribution, result.statistic));
  const double alpha = 1 - std::pow(1 - o.significance, 1.0 / o.test_count);  // Sidak correction
  const double p = result.invalid_fraction, n = double(o.sample_count);
  const bool mass_matches = o.absorbed_samples
                                ? std::abs(result.pdf_integral + p - 1) < 1e-3 + 5 * std::sqrt(p * (1 - p) / n)
                                : result.invalid_fraction == 0 && std::abs(result.pdf_integral - 1) < 1e-3;
  result.passed = result.p_value > alpha && mass_matches;
  result.summary = fmt::format("chi2 = {:.1f}, dof = {}, p = {:.3g} (alpha {:.2g}), pdf integral = {:.6f}, "
                               "invalid samples = {:.2g}, pooled expected = {:.1f}",
                               result.statistic, result.degrees_of_freedom, result.p_value, alpha,
                               result.pdf_integral, result.invalid_fraction, pooled_expected);
  return result;
}

}  // namespace vdbappear::test
