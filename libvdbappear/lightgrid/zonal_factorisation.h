#pragma once
// Zonal-harmonic factorisation of the real SH basis, Eq. (5.3) of the dissertation (Wu 2020):
//   Y_lm(w) = sum_j alpha^m_{l,j} Y_l0(w . w_{l,j}),
// with the lobe directions shared across bands (Appendix C.1): band l uses the first 2l + 1 of
// 2 lmax + 1 directions. By the addition theorem, K_l P_l(w . d) = s_l sum_m Y_lm(d) Y_lm(w) with
// s_l = sqrt(4 pi / (2l + 1)), so with M_l[j][m] = Y_lm(d_j) the weights are alpha_l = M_l^-1 / s_l.
// The directions are chosen by a deterministic search that minimises the largest condition number
// of the M_l over all bands (docs/sh_lightgrid.md says how, and what it reaches).

#include "libvdbappear/math/vector.h"

#include <Eigen/Core>

#include <vector>

namespace vdbappear {

class ZonalFactorisation {
 public:
  explicit ZonalFactorisation(int lmax);

  int lmax() const { return lmax_; }
  // The 2 lmax + 1 shared lobe directions w_{l,j} = directions()[j].
  const std::vector<Vec3>& directions() const { return directions_; }
  // alpha^m_{l,j} as a (2l+1) x (2l+1) matrix: row m + l, column j.
  const Eigen::MatrixXd& weights(int l) const { return weights_[l]; }
  // cond_2(M_l): how much the factorisation can amplify relative errors of band l's ZH integrals.
  double conditionNumber(int l) const { return condition_[l]; }
  double worstConditionNumber() const;

 private:
  int lmax_;
  std::vector<Vec3> directions_;
  std::vector<Eigen::MatrixXd> weights_;
  std::vector<double> condition_;
};

}  // namespace vdbappear
