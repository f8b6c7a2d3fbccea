#pragma once
// A 1-D phase function tabulated on k equal bins of mu = cos(scattering angle) over [-1,1]
// (docs/medium.md §6; the altered phase functions of the similarity paper, Eq. 31). Piecewise
// constant in mu, uniform in phi. mu = -wi . wo (wi and wo both point away).

#include "libvdbappear/math/piecewise_constant.h"
#include "libvdbappear/math/sggx.h"  // PhaseSample

#include <vector>

namespace vdbappear {

class TabulatedPhase {
 public:
  // values: f on each bin, ascending in mu, non-negative, not all zero. Normalised here so that
  // 2 pi sum_b f_b (2/k) = 1; normalisation() returns the factor applied (1 for a normalised table).
  explicit TabulatedPhase(std::vector<double> values);

  int bins() const { return int(values_.size()); }
  double normalisation() const { return normalisation_; }
  double eval(double mu) const;
  double phase(const Vec3& wi, const Vec3& wo) const { return eval(-wi.dot(wo)); }
  PhaseSample sample(const Vec3& wi, const Point2& u) const;

 private:
  std::vector<double> values_;
  PiecewiseConstant1D mu_distribution_;  // over x = (mu + 1) / 2
  double normalisation_ = 1;
};

}  // namespace vdbappear
