#pragma once
// The altered phase function as a table (§5.2 of the similarity paper): the quadratic program of
// Eq. (31), solved with ALGLIB's interior-point QP solver (or from a warm start) and made exact on
// its active set. Light header.

#include <vector>

namespace vdbappear {

struct PhaseTableSolution {
  bool feasible = false;
  std::vector<double> table;  // f on k bins ascending over [-1,1], normalised (docs/medium.md §6)
  double moment_residual = 0; // max_n |(G c)_n - f*_n| of the returned table
  int termination = 0;        // ALGLIB's completion code (> 0: success); 0 if a warm start made it unneeded
  bool warm_started = false;  // solved from the warm start alone, without the interior-point solve
};

// Eq. (31): min |S c|^2 subject to c >= 0 and G c = f*, with the boxcar basis of Eq. (30) on `bins`
// bins, G of Eq. (28)-(29) for the moments given (f*_0 = 1 .. f*_N) and S the (k-2) x k second
// difference ("1D Poisson") matrix. The interior-point solution is then made exact on its active
// set: the bins at 0 are exactly 0, the others solve the equality-constrained problem, and the
// multipliers of the zero bins are non-negative (the KKT conditions, to kKktTolerance), so that the
// support of the table is that of the problem's unique optimum. Bins below kActiveGuess (relative
// to the isotropic 1 / (4 pi)) start in the active set: a start only, which sets the number of
// steps (1e-4 measured fastest), not the result. feasible is false when the solver reports
// infeasibility, the active-set step does not converge, or the result misses a moment by more than
// kMomentTolerance.
inline constexpr double kActiveGuess = 1e-4;
inline constexpr double kKktTolerance = 1e-11;
inline constexpr double kMomentTolerance = 1e-7;
//
// warm_start: the table of a nearby problem on the same bins (the same order at the neighbouring g
// level, say). The active-set step then starts from it instead of from the interior-point solution,
// and the interior-point solve runs only if that does not converge within kWarmStartSteps. The
// optimum is the same either way (the step ends only at a KKT point); only the time differs.
inline constexpr int kWarmStartSteps = 24;
PhaseTableSolution solveAlteredPhaseTable(const std::vector<double>& target_moments, int bins,
                                          const std::vector<double>* warm_start = nullptr);

}  // namespace vdbappear
