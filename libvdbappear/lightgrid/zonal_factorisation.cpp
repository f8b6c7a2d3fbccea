#include "libvdbappear/lightgrid/zonal_factorisation.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/spherical_harmonics.h"

#include <Eigen/LU>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace vdbappear {

namespace {

// M_l[j][m + l] = Y_lm(d_j) for the first 2l + 1 directions.
Eigen::MatrixXd bandMatrix(int l, const std::vector<std::vector<double>>& Y) {
  Eigen::MatrixXd M(2 * l + 1, 2 * l + 1);
  for (int j = 0; j <= 2 * l; ++j)
    for (int m = -l; m <= l; ++m) M(j, m + l) = Y[j][shIndex(l, m)];
  return M;
}

// cond_2(M) = sqrt of the ratio of the extreme eigenvalues of M^T M.
double conditionOf(const Eigen::MatrixXd& M) {
  const Eigen::VectorXd e = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M.transpose() * M, Eigen::EigenvaluesOnly).eigenvalues();
  return e(0) > 0 ? std::sqrt(e(e.size() - 1) / e(0)) : INFINITY;
}

Vec3 randomDirection(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Vec3 d;
  do d = Vec3(normal(rng), normal(rng), normal(rng));
  while (d.squaredNorm() < 1e-12);
  return d.normalized();
}

// The largest condition number over the bands that use direction `j` (bands l with 2l >= j).
double worstCondition(int lmax, int j, const std::vector<std::vector<double>>& Y) {
  double worst = 0;
  for (int l = std::max(1, (j + 1) / 2); l <= lmax; ++l) worst = std::max(worst, conditionOf(bandMatrix(l, Y)));
  return worst;
}

// Hill climbing on one direction at a time from seeded random directions: a move is kept when the
// worst condition number of the bands that use the direction does not grow, with a step radius
// shrinking from 0.3 to 0.01. Seeded, so the directions are the same on every run.
std::vector<Vec3> searchDirections(int lmax) {
  const int count = 2 * lmax + 1;
  std::mt19937_64 rng(0x5a1d2024);
  std::vector<Vec3> d(count);
  std::vector<std::vector<double>> Y(count);
  for (int j = 0; j < count; ++j) {
    d[j] = randomDirection(rng);
    Y[j] = evalSphericalHarmonics(lmax, d[j]);
  }
  std::uniform_int_distribution<int> pick(0, count - 1);
  const int steps = 60 * count;
  for (int step = 0; step < steps; ++step) {
    const int j = pick(rng);
    const double radius = 0.3 * (1.0 - double(step) / steps) + 0.01;
    const double before = worstCondition(lmax, j, Y);
    const Vec3 old_d = d[j];
    const std::vector<double> old_Y = Y[j];
    d[j] = (d[j] + radius * randomDirection(rng)).normalized();
    Y[j] = evalSphericalHarmonics(lmax, d[j]);
    if (worstCondition(lmax, j, Y) > before) {
      d[j] = old_d;
      Y[j] = old_Y;
    }
  }
  return d;
}

}  // namespace

ZonalFactorisation::ZonalFactorisation(int lmax) : lmax_(lmax) {
  if (lmax < 0 || lmax > 20) throw std::invalid_argument("zonal factorisation: lmax must be in [0, 20]");
  directions_ = searchDirections(lmax);
  directions_.resize(2 * lmax + 1);
  std::vector<std::vector<double>> Y;
  for (const Vec3& d : directions_) Y.push_back(evalSphericalHarmonics(lmax, d));
  for (int l = 0; l <= lmax; ++l) {
    const Eigen::MatrixXd M = bandMatrix(l, Y);
    const double s_l = std::sqrt(4 * kPi / (2 * l + 1));
    weights_.push_back(M.inverse() / s_l);
    condition_.push_back(conditionOf(M));
  }
}

double ZonalFactorisation::worstConditionNumber() const {
  return *std::max_element(condition_.begin(), condition_.end());
}

}  // namespace vdbappear
