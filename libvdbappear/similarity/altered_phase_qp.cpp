#include "libvdbappear/similarity/altered_phase_qp.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/similarity/banded_kkt.h"
#include "libvdbappear/similarity/legendre_moments.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <libalglib/optimization.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {
namespace {

// Q = S^T S of the second-difference matrix S ((k-2) x k, rows -1 2 -1): pentadiagonal.
Eigen::SparseMatrix<double> poissonQuadraticTerm(int bins) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int r = 0; r + 2 < bins; ++r) {
    const double row[3] = {-1, 2, -1};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) entries.emplace_back(r + a, r + b, row[a] * row[b]);
  }
  Eigen::SparseMatrix<double> q(bins, bins);
  q.setFromTriplets(entries.begin(), entries.end());  // sums the overlapping rows
  return q;
}

// The upper part of 2 Q in ALGLIB's form (it minimises x^T A x / 2).
alglib::sparsematrix alglibQuadraticTerm(const Eigen::SparseMatrix<double>& q) {
  const int bins = int(q.rows());
  alglib::sparsematrix sparse;
  alglib::sparsecreate(bins, bins, 5 * bins, sparse);
  for (int j = 0; j < q.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(q, j); it; ++it)
      if (it.row() <= it.col() && it.value() != 0) alglib::sparseset(sparse, int(it.row()), int(it.col()), 2 * it.value());
  return sparse;
}

// Scaled unknowns x = 4 pi c (isotropic: x = 1), so that the solver's tolerances are relative.
Eigen::MatrixXd scaledMomentMatrix(int bins, int order) {
  const std::vector<double> g = binMomentMatrix(bins, order);
  Eigen::MatrixXd m(order + 1, bins);
  for (int n = 0; n <= order; ++n)
    for (int i = 0; i < bins; ++i) m(n, i) = g[std::size_t(n) * bins + i] / (4 * kPi);
  return m;
}

Eigen::VectorXd solveQp(const Eigen::SparseMatrix<double>& q, const Eigen::MatrixXd& g, const Eigen::VectorXd& target,
                        int& termination) {
  const int bins = int(g.cols()), rows = int(g.rows());
  alglib::minqpstate state;
  alglib::minqpcreate(bins, state);
  alglib::minqpsetquadratictermsparse(state, alglibQuadraticTerm(q), true);
  alglib::real_2d_array c;
  c.setlength(rows, bins + 1);
  for (int n = 0; n < rows; ++n) {
    for (int i = 0; i < bins; ++i) c(n, i) = g(n, i);
    c(n, bins) = target[n];
  }
  alglib::integer_1d_array types;
  types.setlength(rows);
  for (int n = 0; n < rows; ++n) types[n] = 0;  // equality
  alglib::minqpsetlc(state, c, types);
  alglib::minqpsetbcall(state, 0.0, alglib::fp_posinf);
  alglib::real_1d_array scale;
  scale.setlength(bins);
  for (int i = 0; i < bins; ++i) scale[i] = 1;
  alglib::minqpsetscale(state, scale);
  alglib::minqpsetalgosparseipm(state, 1e-10);
  alglib::minqpoptimize(state);
  alglib::real_1d_array x;
  alglib::minqpreport report;
  alglib::minqpresults(state, x, report);
  termination = int(report.terminationtype);
  Eigen::VectorXd result(bins);
  for (int i = 0; i < bins; ++i) result[i] = x[i];
  return result;
}

// The KKT matrix of the free bins (free_index[i]: bin i's row, -1 for a bin held at 0), for the
// sparse LU that solveBandedKkt falls back to.
Eigen::SparseMatrix<double> kktMatrix(const Eigen::SparseMatrix<double>& q, const Eigen::MatrixXd& g,
                                      const std::vector<int>& free_index, int free_count) {
  const int bins = int(g.cols()), rows = int(g.rows());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(std::size_t(5 * free_count + 2 * rows * free_count));
  for (int j = 0; j < q.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(q, j); it; ++it)
      if (free_index[it.row()] >= 0 && free_index[it.col()] >= 0)
        entries.emplace_back(free_index[it.row()], free_index[it.col()], 2 * it.value());
  for (int n = 0; n < rows; ++n)
    for (int i = 0; i < bins; ++i)
      if (free_index[i] >= 0) {
        entries.emplace_back(free_count + n, free_index[i], g(n, i));
        entries.emplace_back(free_index[i], free_count + n, g(n, i));
      }
  Eigen::SparseMatrix<double> kkt(free_count + rows, free_count + rows);
  kkt.setFromTriplets(entries.begin(), entries.end());
  return kkt;
}

// 2 Q_FF, the Hessian of the free bins F (ascending): Q's bands where the free bins are neighbours.
PentadiagonalMatrix freeBinsHessian(const Eigen::SparseMatrix<double>& q, const std::vector<int>& free_bins) {
  const Eigen::Index n = Eigen::Index(free_bins.size());
  PentadiagonalMatrix h{Eigen::VectorXd(n), Eigen::VectorXd::Zero(std::max<Eigen::Index>(n - 1, 0)),
                        Eigen::VectorXd::Zero(std::max<Eigen::Index>(n - 2, 0))};
  for (Eigen::Index i = 0; i < n; ++i) {
    h.diagonal[i] = 2 * q.coeff(free_bins[i], free_bins[i]);
    if (i + 1 < n && free_bins[i + 1] - free_bins[i] <= 2) h.first[i] = 2 * q.coeff(free_bins[i], free_bins[i + 1]);
    if (i + 2 < n && free_bins[i + 2] - free_bins[i] == 2) h.second[i] = 2 * q.coeff(free_bins[i], free_bins[i + 2]);
  }
  return h;
}

// The exact optimum of Eq. (31) with the bins of `active` held at 0: the KKT system of the
// equality-constrained problem on the free bins F,
//   [2 Q_FF  G_F^T] [x_F   ]   [0]
//   [G_F     0    ] [lambda] = [t],
// by solveBandedKkt (Q_FF is pentadiagonal, G has N + 1 rows), by a sparse LU where that fails.
// False when it is singular (G_F without full row rank: too few free bins for the moments).
bool solveOnFreeBins(const Eigen::SparseMatrix<double>& q, const Eigen::MatrixXd& g, const Eigen::VectorXd& target,
                     const std::vector<bool>& active, Eigen::VectorXd& x, Eigen::VectorXd& lambda) {
  const int bins = int(g.cols()), rows = int(g.rows());
  std::vector<int> free_bins;
  for (int i = 0; i < bins; ++i)
    if (!active[i]) free_bins.push_back(i);
  const int free_count = int(free_bins.size());
  if (free_count < rows) return false;
  Eigen::MatrixXd g_free(rows, free_count);
  for (int i = 0; i < free_count; ++i) g_free.col(i) = g.col(free_bins[i]);
  // Q_FF is positive definite once two bins are held at 0 (Q's null space, the linear tables, then
  // vanishes on the free bins); else only the whole system is regular (G's first rows are the
  // constant and the linear moment).
  const double delta = bins - free_count >= 2 ? 1e-14 : 1e-8;
  Eigen::VectorXd x_free;
  if (!solveBandedKkt(freeBinsHessian(q, free_bins), g_free, Eigen::VectorXd::Zero(free_count), target, delta, x_free, lambda)) {
    std::vector<int> free_index(bins, -1);
    for (int i = 0; i < free_count; ++i) free_index[free_bins[i]] = i;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(free_count + rows);
    rhs.tail(rows) = target;
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(kktMatrix(q, g, free_index, free_count));
    if (lu.info() != Eigen::Success) return false;
    const Eigen::VectorXd solution = lu.solve(rhs);
    if (lu.info() != Eigen::Success) return false;
    x_free = solution.head(free_count);
    lambda = solution.tail(rows);
  }
  if (!x_free.allFinite() || !lambda.allFinite()) return false;
  x = Eigen::VectorXd::Zero(bins);
  for (int i = 0; i < free_count; ++i) x[free_bins[i]] = x_free[i];
  return (g * x - target).cwiseAbs().maxCoeff() <= kMomentTolerance;
}

// Makes the interior-point solution exact on its active set, by a primal active-set method started
// from it (Nocedal and Wright, Algorithm 16.3): bins below kActiveGuess start at 0; each step solves
// the KKT system on the free bins and moves toward that solution as far as x >= 0 allows, a bin
// that reaches 0 on the way joins the active set; at the solution of a set, the active bin with the
// most negative multiplier mu_i = (2 Q x + G^T lambda)_i (the objective would fall if it rose)
// leaves it. It ends when every multiplier of the active set is >= 0 (to kKktTolerance): every zero
// bin is then exactly 0, and the support is a property of the problem, not of the solver's
// tolerance. False if it does not converge.
bool refineOnActiveSet(const Eigen::SparseMatrix<double>& q, const Eigen::MatrixXd& g, const Eigen::VectorXd& target,
                       Eigen::VectorXd& x, int max_steps) {
  const int bins = int(x.size());
  std::vector<bool> active(bins);
  for (int i = 0; i < bins; ++i) {
    active[i] = x[i] < kActiveGuess;
    if (active[i]) x[i] = 0;
  }
  Eigen::VectorXd solution, lambda;
  for (int step = 0; step < max_steps; ++step) {
    if (!solveOnFreeBins(q, g, target, active, solution, lambda)) return false;
    double length = 1;  // of the step toward the solution that keeps x >= 0
    int blocking = -1;
    for (int i = 0; i < bins; ++i) {
      const double p = solution[i] - x[i];
      if (!active[i] && solution[i] < -kKktTolerance && x[i] < length * -p) {
        length = x[i] / -p;
        blocking = i;
      }
    }
    if (blocking >= 0) {
      for (int i = 0; i < bins; ++i)
        if (!active[i]) x[i] += length * (solution[i] - x[i]);
      x[blocking] = 0;
      active[blocking] = true;
      continue;
    }
    const Eigen::VectorXd mu = 2 * (q * solution) + g.transpose() * lambda;
    int leaving = -1;
    for (int i = 0; i < bins; ++i)
      if (active[i] && mu[i] < -kKktTolerance && (leaving < 0 || mu[i] < mu[leaving])) leaving = i;
    x = solution.cwiseMax(0.0);  // free bins within rounding of 0 are 0
    if (leaving < 0) return true;
    active[leaving] = false;
  }
  return false;
}

}  // namespace

// From a start that need not be feasible (a warm start's table solves other moments): a step toward
// the first KKT solution may stop at a bin reaching 0 before G x = t holds, but the method ends only
// at a KKT point of this problem, so a start changes the number of steps, never the optimum.
PhaseTableSolution solveAlteredPhaseTable(const std::vector<double>& target_moments, int bins,
                                          const std::vector<double>* warm_start) {
  const int order = int(target_moments.size()) - 1;
  if (order < 0 || bins < order + 3) throw std::invalid_argument("solveAlteredPhaseTable: need moments and more bins than moments + 2");
  if (warm_start && int(warm_start->size()) != bins) throw std::invalid_argument("solveAlteredPhaseTable: a warm start on other bins");
  const Eigen::MatrixXd g = scaledMomentMatrix(bins, order);
  const Eigen::SparseMatrix<double> q = poissonQuadraticTerm(bins);
  Eigen::VectorXd target(order + 1);
  for (int n = 0; n <= order; ++n) target[n] = target_moments[n];
  PhaseTableSolution solution;
  Eigen::VectorXd x(bins);
  bool polished = false;
  if (warm_start) {
    for (int i = 0; i < bins; ++i) x[i] = 4 * kPi * (*warm_start)[i];
    polished = refineOnActiveSet(q, g, target, x, kWarmStartSteps);
    solution.warm_started = polished;
  }
  if (!polished) {
    x = solveQp(q, g, target, solution.termination);
    polished = solution.termination > 0 && refineOnActiveSet(q, g, target, x, 4 * bins);
  }
  solution.moment_residual = (g * x - target).cwiseAbs().maxCoeff();
  solution.feasible = polished && solution.moment_residual <= kMomentTolerance;
  solution.table.resize(bins);
  for (int i = 0; i < bins; ++i) solution.table[i] = std::max(0.0, x[i]) / (4 * kPi);
  return solution;
}

}  // namespace vdbappear
