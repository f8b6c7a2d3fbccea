#include "libvdbappear/similarity/altered_phase_qp.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/similarity/legendre_moments.h"

#include <Eigen/Dense>
#include <libalglib/optimization.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {
namespace {

// Q = S^T S of the second-difference matrix S ((k-2) x k, rows -1 2 -1): pentadiagonal, upper part.
alglib::sparsematrix poissonQuadraticTerm(int bins) {
  Eigen::MatrixXd q = Eigen::MatrixXd::Zero(bins, bins);
  for (int r = 0; r + 2 < bins; ++r) {
    const double row[3] = {-1, 2, -1};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) q(r + a, r + b) += row[a] * row[b];
  }
  alglib::sparsematrix sparse;
  alglib::sparsecreate(bins, bins, 5 * bins, sparse);
  for (int i = 0; i < bins; ++i)
    for (int j = i; j < std::min(bins, i + 3); ++j)
      if (q(i, j) != 0) alglib::sparseset(sparse, i, j, 2 * q(i, j));  // ALGLIB minimises x^T A x / 2
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

Eigen::VectorXd solveQp(const Eigen::MatrixXd& g, const Eigen::VectorXd& target, int& termination) {
  const int bins = int(g.cols()), rows = int(g.rows());
  alglib::minqpstate state;
  alglib::minqpcreate(bins, state);
  alglib::minqpsetquadratictermsparse(state, poissonQuadraticTerm(bins), true);
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

// Zeroes bins below kZeroBin and re-imposes g x = target on the others (least-norm correction).
// Returns false if the correction would make a bin negative.
bool polish(const Eigen::MatrixXd& g, const Eigen::VectorXd& target, Eigen::VectorXd& x) {
  std::vector<int> positive;
  for (int i = 0; i < x.size(); ++i) {
    if (x[i] < kZeroBin) x[i] = 0;
    else positive.push_back(i);
  }
  if (positive.empty()) return false;
  Eigen::MatrixXd gp(g.rows(), Eigen::Index(positive.size()));
  for (std::size_t j = 0; j < positive.size(); ++j) gp.col(Eigen::Index(j)) = g.col(positive[j]);
  const Eigen::VectorXd residual = target - g * x;
  const Eigen::VectorXd correction = gp.transpose() * (gp * gp.transpose()).ldlt().solve(residual);
  for (std::size_t j = 0; j < positive.size(); ++j) x[positive[j]] += correction[Eigen::Index(j)];
  return x.minCoeff() >= 0;
}

}  // namespace

PhaseTableSolution solveAlteredPhaseTable(const std::vector<double>& target_moments, int bins) {
  const int order = int(target_moments.size()) - 1;
  if (order < 0 || bins < order + 3) throw std::invalid_argument("solveAlteredPhaseTable: need moments and more bins than moments + 2");
  const Eigen::MatrixXd g = scaledMomentMatrix(bins, order);
  Eigen::VectorXd target(order + 1);
  for (int n = 0; n <= order; ++n) target[n] = target_moments[n];
  PhaseTableSolution solution;
  Eigen::VectorXd x = solveQp(g, target, solution.termination);
  const bool polished = solution.termination > 0 && polish(g, target, x);
  solution.moment_residual = (g * x - target).cwiseAbs().maxCoeff();
  solution.feasible = polished && solution.moment_residual <= kMomentTolerance;
  solution.table.resize(bins);
  for (int i = 0; i < bins; ++i) solution.table[i] = std::max(0.0, x[i]) / (4 * kPi);
  return solution;
}

}  // namespace vdbappear
