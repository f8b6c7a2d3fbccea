#include "libvdbappear/surface/height_downsample.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace vdbappear {

namespace {

void checkFactor(const HeightField& fine, int factor) {
  if (factor < 1 || fine.cellsX() % factor != 0 || fine.cellsY() % factor != 0)
    throw std::invalid_argument("the factor " + std::to_string(factor) + " does not divide the map's " +
                                std::to_string(fine.cellsX()) + " x " + std::to_string(fine.cellsY()) +
                                " cells (a map of (n + 1)^2 pixels has n^2 cells)");
}

// The rows of Eq. (4.10) as a sparse least-squares system A h = b over the coarse vertices.
class SlopeSystem {
 public:
  SlopeSystem(const HeightField& fine, const HeightField& coarse, double w) : coarse_(coarse) {
    const int factor = fine.cellsX() / coarse.cellsX();
    const double L = coarse.cellSize();
    for (int v = 0; v < coarse.cellsY(); ++v)
      for (int u = 0; u < coarse.cellsX(); ++u) {
        const Point2 target = fine.averageSlope(u * factor, v * factor, factor);  // Eq. (4.1)
        // Eq. (4.9): s~ = ((h11 + h10 - h01 - h00) / 2, (h11 + h01 - h10 - h00) / 2) / L.
        addRow({{u + 1, v + 1, 1}, {u + 1, v, 1}, {u, v + 1, -1}, {u, v, -1}}, 1 / (2 * L), target.x());
        addRow({{u + 1, v + 1, 1}, {u, v + 1, 1}, {u + 1, v, -1}, {u, v, -1}}, 1 / (2 * L), target.y());
      }
    const double scale = std::sqrt(w) / L;
    for (int v = 1; v < coarse.cellsY(); ++v)
      for (int u = 1; u < coarse.cellsX(); ++u)
        addRow({{u + 1, v, 1}, {u - 1, v, 1}, {u, v + 1, 1}, {u, v - 1, 1}, {u, v, -4}}, scale, 0);
  }

  Eigen::VectorXd solve() const {
    Eigen::SparseMatrix<double> A(static_cast<Eigen::Index>(b_.size()), coarse_.verticesX() * coarse_.verticesY());
    A.setFromTriplets(entries_.begin(), entries_.end());
    const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(b_.data(), static_cast<Eigen::Index>(b_.size()));
    // Conjugate gradients on the normal equations from h = 0 stay orthogonal to the null space
    // (the constant; the checkerboard too when no vertex is interior): the least-norm solution.
    Eigen::LeastSquaresConjugateGradient<Eigen::SparseMatrix<double>> solver;
    solver.setTolerance(1e-12);
    solver.setMaxIterations(100000);
    solver.compute(A);
    return solver.solve(b);
  }

 private:
  struct Term {
    int u, v;
    double coefficient;
  };

  void addRow(std::initializer_list<Term> terms, double scale, double target) {
    const int row = static_cast<int>(b_.size());
    for (const Term& t : terms) entries_.emplace_back(row, t.v * coarse_.verticesX() + t.u, scale * t.coefficient);
    b_.push_back(target);
  }

  const HeightField& coarse_;
  std::vector<Eigen::Triplet<double>> entries_;
  std::vector<double> b_;
};

}  // namespace

HeightField downsampleHeights(const HeightField& fine, const HeightDownsampleSettings& settings) {
  checkFactor(fine, settings.factor);
  if (!(settings.smoothness_weight >= 0)) throw std::invalid_argument("the smoothness weight must be >= 0");
  HeightField coarse(fine.cellsX() / settings.factor, fine.cellsY() / settings.factor,
                     fine.cellSize() * settings.factor);
  const Eigen::VectorXd h = SlopeSystem(fine, coarse, settings.smoothness_weight).solve();
  for (int j = 0; j < coarse.verticesY(); ++j)
    for (int i = 0; i < coarse.verticesX(); ++i) coarse.at(i, j) = h[j * coarse.verticesX() + i];
  const double shift = fine.meanHeight() - coarse.meanHeight();
  for (int j = 0; j < coarse.verticesY(); ++j)
    for (int i = 0; i < coarse.verticesX(); ++i) coarse.at(i, j) += shift;
  return coarse;
}

HeightField decimateHeights(const HeightField& fine, int factor) {
  checkFactor(fine, factor);
  HeightField coarse(fine.cellsX() / factor, fine.cellsY() / factor, fine.cellSize() * factor);
  for (int j = 0; j < coarse.verticesY(); ++j)
    for (int i = 0; i < coarse.verticesX(); ++i) coarse.at(i, j) = fine.at(i * factor, j * factor);
  return coarse;
}

double slopeErrorRms(const HeightField& fine, const HeightField& coarse) {
  const int factor = fine.cellsX() / coarse.cellsX();
  double sum = 0;
  for (int v = 0; v < coarse.cellsY(); ++v)
    for (int u = 0; u < coarse.cellsX(); ++u)
      sum += (coarse.cellSlope(u, v) - fine.averageSlope(u * factor, v * factor, factor)).squaredNorm();
  return std::sqrt(sum / (static_cast<double>(coarse.cellsX()) * coarse.cellsY()));
}

}  // namespace vdbappear
