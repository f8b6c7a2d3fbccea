#include "libvdbappear/similarity/legendre_moments.h"

#include "libvdbappear/math/constants.h"

#include <cmath>
#include <stdexcept>

namespace vdbappear {

std::vector<double> henyeyGreensteinMoments(double g, int order) {
  std::vector<double> f(order + 1, 1.0);
  for (int n = 1; n <= order; ++n) f[n] = f[n - 1] * g;
  return f;
}

std::vector<double> legendreIntegrals(double a, double b, int order) {
  const std::vector<double> pa = legendrePolynomials(order + 1, a), pb = legendrePolynomials(order + 1, b);
  std::vector<double> integrals(order + 1);
  integrals[0] = b - a;
  for (int n = 1; n <= order; ++n)
    integrals[n] = ((pb[n + 1] - pb[n - 1]) - (pa[n + 1] - pa[n - 1])) / (2 * n + 1);
  return integrals;
}

static double binEdge(int i, int bins) { return -1 + 2.0 * i / bins; }

std::vector<double> binMomentMatrix(int bins, int order) {
  if (bins < 1 || order < 0) throw std::invalid_argument("binMomentMatrix: need bins >= 1 and order >= 0");
  std::vector<double> g(std::size_t(order + 1) * bins);
  for (int i = 0; i < bins; ++i) {
    const std::vector<double> integrals = legendreIntegrals(binEdge(i, bins), binEdge(i + 1, bins), order);
    for (int n = 0; n <= order; ++n) g[std::size_t(n) * bins + i] = 2 * kPi * integrals[n];
  }
  return g;
}

std::vector<double> tableMoments(const std::vector<double>& table, int order) {
  const int bins = int(table.size());
  const std::vector<double> g = binMomentMatrix(bins, order);
  std::vector<double> moments(order + 1, 0.0);
  for (int n = 0; n <= order; ++n)
    for (int i = 0; i < bins; ++i) moments[n] += g[std::size_t(n) * bins + i] * table[i];
  return moments;
}

std::vector<double> normalisedTable(std::vector<double> table) {
  double integral = 0;
  for (double f : table) integral += f;
  integral *= 2 * kPi * 2.0 / double(table.size());
  if (!(integral > 0) || !std::isfinite(integral)) throw std::invalid_argument("phase table: integrates to zero or is not finite");
  for (double& f : table) f /= integral;
  return table;
}

// integral_{-1}^{mu} 2 pi HG(t, g) dt, the CDF of mu.
static double henyeyGreensteinCdf(double mu, double g) {
  if (std::abs(g) < 1e-6) return (mu + 1) / 2;
  const double denom = std::sqrt(1 + g * g - 2 * g * mu);
  return (1 - g * g) / (2 * g) * (1 / denom - 1 / (1 + g));
}

std::vector<double> tabulateHenyeyGreenstein(double g, int bins) {
  std::vector<double> table(bins);
  for (int i = 0; i < bins; ++i) {
    const double a = binEdge(i, bins), b = binEdge(i + 1, bins);
    table[i] = (henyeyGreensteinCdf(b, g) - henyeyGreensteinCdf(a, g)) / (2 * kPi * (b - a));
  }
  return normalisedTable(table);
}

double tableSupport(const std::vector<double>& table) {
  int positive = 0;
  for (double f : table) positive += f > 0;
  return double(positive) / double(table.size());
}

std::vector<double> monomialMoments(const std::vector<double>& legendre_moments) {
  const int order = int(legendre_moments.size()) - 1;
  std::vector<double> gamma(order + 1);
  std::vector<double> a{1.0};  // t^n in the Legendre basis, starting at n = 0
  for (int n = 0; n <= order; ++n) {
    double sum = 0;
    for (int j = 0; j <= n; ++j) sum += a[j] * legendre_moments[j];
    gamma[n] = sum / legendre_moments[0];
    std::vector<double> next(n + 2, 0.0);  // t * sum_j a_j P_j
    for (int j = 0; j <= n; ++j) {
      next[j + 1] += a[j] * (j + 1) / (2.0 * j + 1);
      if (j > 0) next[j - 1] += a[j] * j / (2.0 * j + 1);
    }
    a = std::move(next);
  }
  return gamma;
}

}  // namespace vdbappear
