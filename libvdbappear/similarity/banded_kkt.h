#pragma once
// The KKT system of an equality-constrained quadratic program whose Hessian is pentadiagonal and
// whose few constraint rows are dense (the QP of Eq. (31) on its free bins, altered_phase_qp.h):
//   [H  B^T] [x     ]   [r1]
//   [B  0  ] [lambda] = [r2],   H n x n symmetric pentadiagonal, B m x n, m << n.
// Solved through the LDL^T of its quasi-definite neighbour [H + delta I, B^T; B, -delta I], which
// exists in any order (Vanderbei 1995): in the natural order the bins' block is a band factor and
// the multipliers' block the dense m x m Schur complement, O(n m^2) in all. Iterative refinement
// against the exact system removes what delta changed. Eigen types; light header.

#include <Eigen/Core>

namespace vdbappear {

// A symmetric pentadiagonal matrix by its bands: diagonal[i] = H(i,i), first[i] = H(i,i+1),
// second[i] = H(i,i+2).
struct PentadiagonalMatrix {
  Eigen::VectorXd diagonal, first, second;  // sizes n, n-1, n-2
  Eigen::Index size() const { return diagonal.size(); }
  Eigen::VectorXd operator*(const Eigen::VectorXd& v) const;
};

// delta: 1e-14 where H is positive definite; where H is singular but the whole system is not (H's
// null space meets no null vector of B), H + delta I has eigenvalues delta, the factor is accurate
// to about eps / delta, and each refinement step gains that factor: 1e-8 converges in 2-3 steps.
// False if the residual of the exact system is still above 1e-13 after 8 steps, or the factor
// breaks down (the caller then needs another method); x and lambda are then unspecified.
bool solveBandedKkt(const PentadiagonalMatrix& h, const Eigen::MatrixXd& b, const Eigen::VectorXd& r1,
                    const Eigen::VectorXd& r2, double delta, Eigen::VectorXd& x, Eigen::VectorXd& lambda);

}  // namespace vdbappear
