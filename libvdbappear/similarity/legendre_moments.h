#pragma once
// Legendre moments of 1-D phase functions (similarity paper, Eq. 7-8):
//   f_n = 2 pi integral_{-1}^{1} f(mu) P_n(mu) dmu,
// so f_0 = 1 for a normalised phase function and f_1 is the mean cosine. mu is the cosine of the
// scattering angle (mu = 1: forward), as in docs/medium.md §6. Light header.

#include "libvdbappear/math/legendre.h"

#include <vector>

namespace vdbappear {

// Eq. (8) of HG(g): f_n = g^n, n = 0..order.
std::vector<double> henyeyGreensteinMoments(double g, int order);

// integral_a^b P_n(t) dt for n = 0..order: (P_{n+1} - P_{n-1}) / (2n+1) at the bounds, exact.
std::vector<double> legendreIntegrals(double a, double b, int order);

// Eq. (28)-(30): G(n, i) = 2 pi integral over boxcar bin i of P_n, for k bins ascending over
// [-1,1] and n = 0..order. Row-major, (order+1) x k. The moments of a table c are G c.
std::vector<double> binMomentMatrix(int bins, int order);

// Eq. (8) of a piecewise-constant table on equal bins ascending over [-1,1], exact.
std::vector<double> tableMoments(const std::vector<double>& table, int order);

// The table's values scaled so that 2 pi sum_b f_b (2/k) = 1 (docs/medium.md §6).
std::vector<double> normalisedTable(std::vector<double> table);

// Bin averages of HG(g), exact (from its CDF in mu), normalised as above.
std::vector<double> tabulateHenyeyGreenstein(double g, int bins);

// §7.3: the share of the domain where the table is positive (bins with f > 0, over k).
double tableSupport(const std::vector<double>& table);

// Monomial moments gamma_n = integral f(t) t^n dt over [-1,1], divided by gamma_0 = 1 / (2 pi), from
// the Legendre moments f_0 (= 1) .. f_N. Through t^n = sum_j a_nj P_j(t) (built by t P_j =
// ((j+1) P_{j+1} + j P_{j-1}) / (2j+1)): gamma_n / gamma_0 = sum_j a_nj f_j.
std::vector<double> monomialMoments(const std::vector<double>& legendre_moments);

}  // namespace vdbappear
