#pragma once
// Theorem 1 of the similarity paper (the truncated Hausdorff moment problem, Curto and Fialkow
// 1991): whether a non-negative phase function with given Legendre moments f_0 .. f_N exists. Light
// header.

#include <vector>

namespace vdbappear {

// Relative tolerance of the positive semi-definiteness test: a Hankel matrix passes when its
// smallest eigenvalue is >= -kHankelTolerance * (its largest eigenvalue magnitude, at least 1).
inline constexpr double kHankelTolerance = 1e-9;

struct MomentExistence {
  bool exists = false;
  // The smallest eigenvalue, over the matrices of Eq. (25) or (26), divided by the magnitude of
  // the largest (at least 1): >= 0 inside the moment space, < 0 outside, about 0 on its boundary
  // (where only sums of point masses have these moments).
  double margin = 0;
};

// Eq. (24)-(26), with the monomial moments gamma_n of monomialMoments() (gamma_0 = 1):
//   N = 2k+1: U_{k+1} - V_{k+1} >= 0 and U_{k+1} + V_{k+1} >= 0;
//   N = 2k:   U_{k+1} >= 0 and U_k - W_k >= 0,
// with U_n(i,j) = gamma_{i+j-2}, V_n(i,j) = gamma_{i+j-1}, W_n(i,j) = gamma_{i+j}. The paper's
// IFEXISTS(): f_0 must be 1 (> 0).
MomentExistence checkMomentsExist(const std::vector<double>& legendre_moments);

}  // namespace vdbappear
