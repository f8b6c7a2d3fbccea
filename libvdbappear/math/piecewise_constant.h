#pragma once
// Piecewise-constant densities on [0,1) and [0,1)^2, sampled by inverting their CDFs
// (pbrt-v4, §A.5 "PiecewiseConstant1D/2D"). Used for tabulated phase functions and for
// importance-sampling environment maps.

#include "libvdbappear/math/vector.h"

#include <vector>

namespace vdbappear {

class PiecewiseConstant1D {
 public:
  PiecewiseConstant1D() = default;
  // f: non-negative values of n equal bins on [0,1). If they sum to 0, sampling is uniform.
  explicit PiecewiseConstant1D(std::vector<double> f);

  int size() const { return int(f_.size()); }
  double integral() const { return integral_; }  // of f over [0,1)

  // x in [0,1) with density pdf(x) = f(x) / integral (uniform if the integral is 0); `bin` receives its bin.
  double sample(double u, double* pdf, int* bin = nullptr) const;
  double pdf(double x) const;
  double pdfOfBin(int bin) const;

 private:
  std::vector<double> f_;
  std::vector<double> cdf_;  // size n + 1
  double integral_ = 0;
};

class PiecewiseConstant2D {
 public:
  PiecewiseConstant2D() = default;
  // f: row-major, nv rows (v) of nu columns (u); non-negative.
  PiecewiseConstant2D(const std::vector<double>& f, int nu, int nv);

  double integral() const { return marginal_.integral(); }
  // (u, v) in [0,1)^2 with pdf(u, v) = f / integral.
  Point2 sample(const Point2& u, double* pdf) const;
  double pdf(const Point2& p) const;

 private:
  std::vector<PiecewiseConstant1D> conditional_;  // one per row v
  PiecewiseConstant1D marginal_;
};

}  // namespace vdbappear
