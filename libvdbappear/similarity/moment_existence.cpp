#include "libvdbappear/similarity/moment_existence.h"

#include "libvdbappear/similarity/legendre_moments.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {
namespace {

// The n x n Hankel matrix H(i,j) = gamma[i + j + shift], 0-based: Eq. (24)'s U_n is shift 0, V_n
// shift 1, W_n shift 2.
Eigen::MatrixXd hankel(const std::vector<double>& gamma, int n, int shift) {
  Eigen::MatrixXd h(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) h(i, j) = gamma[i + j + shift];
  return h;
}

// Smallest eigenvalue over the largest magnitude (at least 1); +inf for an empty matrix.
double relativeMinEigenvalue(const Eigen::MatrixXd& m) {
  if (m.rows() == 0) return INFINITY;
  const Eigen::VectorXd eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m, Eigen::EigenvaluesOnly).eigenvalues();
  const double scale = std::max(1.0, eigenvalues.cwiseAbs().maxCoeff());
  return eigenvalues.minCoeff() / scale;
}

}  // namespace

MomentExistence checkMomentsExist(const std::vector<double>& legendre_moments) {
  if (legendre_moments.empty() || !(legendre_moments[0] > 0))
    throw std::invalid_argument("checkMomentsExist: f_0 must be positive");
  const std::vector<double> gamma = monomialMoments(legendre_moments);
  const int order = int(gamma.size()) - 1;
  const int k = order / 2;
  double margin;
  if (order % 2 == 1) {  // Eq. (25)
    const Eigen::MatrixXd u = hankel(gamma, k + 1, 0), v = hankel(gamma, k + 1, 1);
    margin = std::min(relativeMinEigenvalue(u - v), relativeMinEigenvalue(u + v));
  } else {  // Eq. (26)
    const Eigen::MatrixXd u = hankel(gamma, k + 1, 0);
    const Eigen::MatrixXd uk = hankel(gamma, k, 0), wk = hankel(gamma, k, 2);
    margin = std::min(relativeMinEigenvalue(u), relativeMinEigenvalue(uk - wk));
  }
  return {margin >= -kHankelTolerance, margin};
}

}  // namespace vdbappear
