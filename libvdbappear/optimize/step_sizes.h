#pragma once
// Step sizes of the stochastic gradient descent, Eq. (17)-(18) of the downsampling paper:
//   theta^(t+1) = theta^(t) - delta_t dE/dtheta,   delta_t = A / (t + b),  t = 1, 2, ...
// The paper's A is diagonal, a_kj per factor, tuned by hand on a subset of the training set. Here
// A follows from the Jacobian J of the residuals of Eq. 14 (the gradient images of the iterations:
// no extra renders), with H = 2 J^T J the Gauss-Newton approximation of E's Hessian, averaged over
// the iterations so far (weight_optimizer.h), and D = diag(H). Two rules:
//
//   newton (default): A = (1 + b) D^-1/2 G^+ D^-1/2 with G = D^-1/2 H D^-1/2 (unit diagonal) and
//     G^+ its inverse on the eigen-directions of G with eigenvalue >= kNewtonKeep (0 elsewhere): the
//     first step is a Gauss-Newton step along every direction the images determine well, later
//     steps shrink as (1 + b) / (t + b) and so average the Monte Carlo noise of the gradients (b = 1:
//     each iterate is the running mean of the Newton estimates of a quadratic E). Directions of
//     little curvature (two lobes of one cluster that change the images almost alike: their
//     difference) would take huge, noise-driven steps and are left at the naive weights, the
//     paper's starting point. kNewtonKeep = 0.01 from the spectra of G measured on the coloured
//     twill (2 clusters, 2 lobes, colour scales: 0, 0, 0.0038, 0.0050 | 0.11, 0.12, 0.63, 1.2, 2.3,
//     5.7) and on a twill rendered with known factors (0, 0, 0.0007, 0.0013 | 0.029, 0.040, 0.19,
//     1.0, 1.7, 7.1): below it the two colour-scale gauges and the two lobe differences; above it
//     the directions that tell clusters apart, which 0.1 dropped, leaving the known factors 10%
//     off. Needed because the factors are strongly correlated: on the coloured
//     twill (2 clusters, 2 lobes, colour scales) the four w_kj change the images almost alike.
//   diagonal (the paper's form): a_p = eta (1 + b) / H_pp with eta = min(1, 1 / lambda_max(D^-1/2 H
//     D^-1/2)): the largest diagonally preconditioned step that overshoots along no direction. With
//     correlated factors eta is small (0.16 on the coloured twill), and the directions of lesser
//     curvature converge slowly.
//
// A parameter that changes no image (H_pp = 0) does not move. Light header.

#include "libvdbappear/optimize/training_error.h"
#include "libvdbappear/optimize/weight_factors.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace vdbappear {

enum class StepRule { kNewton, kDiagonal };
inline constexpr double kNewtonKeep = 0.01;
const char* stepRuleName(StepRule rule);        // "newton", "diagonal"
StepRule parseStepRule(const std::string& name);  // throws std::invalid_argument

struct StepSizes {
  StepRule rule = StepRule::kNewton;
  std::vector<double> A;  // P x P, row-major (diagonal rule: a_p on the diagonal)
  double b = 1;
  double eta = 1;         // diagonal rule: the safety factor
  int parameters() const;
  // delta_t dE/dtheta, the change of Eq. 17 (to subtract).
  std::vector<double> update(const std::vector<double>& gradient, int t) const;
  // The diagonal of delta_t, for logs.
  std::vector<double> diagonal(int t) const;
  nlohmann::json toJson() const;
  static StepSizes fromJson(const nlohmann::json& json);  // throws std::invalid_argument
};

// H = 2 sum_r J_r J_r^T over the residuals, J_r = dr/dtheta (chain rule of the factors, with the
// colour-scale gauge), P x P, and D_p = 2 sum_r (dr/dtheta_p)^2 without the gauge: the curvature of
// each parameter alone, the scale the rules measure directions in. (With the gauge a lobe factor
// of a colour-scale cluster keeps only the balance of the lobes, whose curvature would pass for
// that of a whole parameter.)
struct GaussNewton {
  std::vector<double> H;  // P x P
  std::vector<double> D;  // P
  GaussNewton& operator+=(const GaussNewton& o);
  GaussNewton scaled(double factor) const;
};
GaussNewton gaussNewton(const std::vector<Residual>& residuals, const WeightFactors& factors);
// The step sizes of a rule; scale multiplies A (1: the rules above; for studies of the rules).
StepSizes stepSizesFrom(const GaussNewton& gauss_newton, StepRule rule, double b = 1, double scale = 1);
// stepSizesFrom(gaussNewtonMatrix(residuals, factors), ...).
StepSizes tuneStepSizes(const std::vector<Residual>& residuals, const WeightFactors& factors, StepRule rule,
                        double b = 1, double scale = 1);

}  // namespace vdbappear
