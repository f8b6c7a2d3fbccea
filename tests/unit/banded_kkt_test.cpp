// The banded KKT solver of the similarity QP (similarity/banded_kkt.h) against a dense LU of the
// same system: a positive definite Hessian, the singular Hessian of Eq. (31) with every bin free
// (second differences: the linear vectors are its null space, which the constant and linear moment
// rows of B make regular), and a negative control whose system is singular.
#include "libvdbappear/similarity/banded_kkt.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <random>

using namespace vdbappear;

namespace {

Eigen::MatrixXd dense(const PentadiagonalMatrix& h) {
  const Eigen::Index n = h.size();
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) m(i, i) = h.diagonal[i];
  for (Eigen::Index i = 0; i + 1 < n; ++i) m(i, i + 1) = m(i + 1, i) = h.first[i];
  for (Eigen::Index i = 0; i + 2 < n; ++i) m(i, i + 2) = m(i + 2, i) = h.second[i];
  return m;
}

// 2 S^T S of the (n-2) x n second-difference matrix S: the Hessian of Eq. (31).
PentadiagonalMatrix secondDifferenceHessian(int n) {
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(n - 2, n);
  for (int r = 0; r + 2 < n; ++r) s.row(r).segment(r, 3) << -1, 2, -1;
  const Eigen::MatrixXd q = 2 * s.transpose() * s;
  PentadiagonalMatrix h{q.diagonal(), Eigen::VectorXd(n - 1), Eigen::VectorXd(n - 2)};
  for (int i = 0; i + 1 < n; ++i) h.first[i] = q(i, i + 1);
  for (int i = 0; i + 2 < n; ++i) h.second[i] = q(i, i + 2);
  return h;
}

// Rows 0 and 1: constant and linear in the bin (as the Legendre moments P0, P1 of bins are); the
// others random.
Eigen::MatrixXd constraintRows(int rows, int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd b(rows, n);
  for (int i = 0; i < n; ++i) {
    b(0, i) = 1.0 / n;
    b(1, i) = (i + 0.5) / n * 2 - 1;
    for (int r = 2; r < rows; ++r) b(r, i) = u(rng);
  }
  return b;
}

// [x; lambda] of the exact system by a dense LU in long double (the singular Hessian's systems have
// condition numbers near 1e9: a double LU would be the less accurate of the two).
Eigen::VectorXd denseSolve(const PentadiagonalMatrix& h, const Eigen::MatrixXd& b, const Eigen::VectorXd& r1,
                           const Eigen::VectorXd& r2) {
  using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  using VectorL = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
  const Eigen::Index n = h.size(), m = b.rows();
  MatrixL kkt = MatrixL::Zero(n + m, n + m);
  kkt.topLeftCorner(n, n) = dense(h).cast<long double>();
  kkt.topRightCorner(n, m) = b.transpose().cast<long double>();
  kkt.bottomLeftCorner(m, n) = b.cast<long double>();
  VectorL rhs(n + m);
  rhs << r1.cast<long double>(), r2.cast<long double>();
  return VectorL(kkt.partialPivLu().solve(rhs)).cast<double>();
}

// The right-hand sides of Eq. (31)'s systems: r1 = 0 and the moments r2 = B x0 of a table x0 (here
// random in [0, 1]); r1 random as well when the Hessian is well conditioned.
// The exact system's residual is what solveBandedKkt guarantees (1e-13); the error against the
// reference is that times the condition number, so `tolerance` is relative to the solution's size.
void expectAgreesWithDense(const PentadiagonalMatrix& h, const Eigen::MatrixXd& b, double delta, bool random_r1,
                           double tolerance, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd r1 = Eigen::VectorXd::Zero(h.size()), x0(h.size());
  for (auto& v : x0) v = (1 + u(rng)) / 2;
  if (random_r1)
    for (auto& v : r1) v = u(rng);
  const Eigen::VectorXd r2 = b * x0;
  Eigen::VectorXd x, lambda;
  ASSERT_TRUE(solveBandedKkt(h, b, r1, r2, delta, x, lambda)) << "n " << h.size() << " rows " << b.rows();
  EXPECT_LE((r1 - h * x - b.transpose() * lambda).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LE((r2 - b * x).cwiseAbs().maxCoeff(), 1e-13);
  const Eigen::VectorXd reference = denseSolve(h, b, r1, r2);
  const double scale = reference.cwiseAbs().maxCoeff();
  EXPECT_LE((x - reference.head(h.size())).cwiseAbs().maxCoeff(), tolerance * scale) << "n " << h.size() << " rows " << b.rows();
  EXPECT_LE((lambda - reference.tail(b.rows())).cwiseAbs().maxCoeff(), tolerance * scale) << "n " << h.size() << " rows " << b.rows();
}

TEST(BandedKkt, PositiveDefiniteHessianAgreesWithADenseSolve) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n : {8, 40, 360}) {
    PentadiagonalMatrix h{Eigen::VectorXd(n), Eigen::VectorXd(n - 1), Eigen::VectorXd(n - 2)};
    for (int i = 0; i < n; ++i) h.diagonal[i] = 6 + u(rng);  // diagonally dominant
    for (int i = 0; i + 1 < n; ++i) h.first[i] = u(rng);
    for (int i = 0; i + 2 < n; ++i) h.second[i] = u(rng);
    expectAgreesWithDense(h, constraintRows(4, n, rng), 1e-14, true, 1e-12, rng);
  }
}

// Condition numbers near 1e9 at n = 360 (the second differences' smallest non-zero eigenvalue is
// about (pi / n)^4): errors up to 1e-9 of the solution's size measured, 1e-8 allowed.
TEST(BandedKkt, SingularHessianWithRegularSystemAgreesWithADenseSolve) {
  std::mt19937 rng(5);
  for (int n : {40, 360})
    for (int rows : {2, 4, 6}) expectAgreesWithDense(secondDifferenceHessian(n), constraintRows(rows, n, rng), 1e-8, false, 1e-8, rng);
}

// Negative control: without the linear row, the linear vector is a null vector of the whole system.
TEST(BandedKkt, RefusesASingularSystem) {
  std::mt19937 rng(7);
  Eigen::MatrixXd b = constraintRows(3, 40, rng);
  b.row(1) = b.row(2);  // the linear row replaced: rank 2, and H's linear null vector is left free
  b.row(2) *= 0.5;
  Eigen::VectorXd x, lambda;
  EXPECT_FALSE(solveBandedKkt(secondDifferenceHessian(40), b, Eigen::VectorXd::Zero(40), Eigen::VectorXd::Ones(3), 1e-8, x, lambda));
}

}  // namespace
