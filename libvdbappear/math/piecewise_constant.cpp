#include "libvdbappear/math/piecewise_constant.h"

#include <algorithm>
#include <stdexcept>

namespace vdbappear {

PiecewiseConstant1D::PiecewiseConstant1D(std::vector<double> f) : f_(std::move(f)), cdf_(f_.size() + 1, 0.0) {
  if (f_.empty()) throw std::invalid_argument("PiecewiseConstant1D: no bins");
  const double n = double(f_.size());
  for (std::size_t i = 0; i < f_.size(); ++i) {
    if (!(f_[i] >= 0)) throw std::invalid_argument("PiecewiseConstant1D: negative or NaN value");
    cdf_[i + 1] = cdf_[i] + f_[i] / n;
  }
  integral_ = cdf_.back();
  for (std::size_t i = 1; i < cdf_.size(); ++i)
    cdf_[i] = integral_ > 0 ? cdf_[i] / integral_ : double(i) / n;
  cdf_.back() = 1.0;
}

double PiecewiseConstant1D::pdfOfBin(int bin) const {
  return integral_ > 0 ? f_[bin] / integral_ : 1.0;
}

double PiecewiseConstant1D::sample(double u, double* pdf, int* bin) const {
  // The last i with cdf[i] <= u, skipping empty bins.
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const int i = std::clamp(int(it - cdf_.begin()) - 1, 0, size() - 1);
  const double width = cdf_[i + 1] - cdf_[i];
  const double du = width > 0 ? (u - cdf_[i]) / width : 0.5;
  if (pdf) *pdf = pdfOfBin(i);
  if (bin) *bin = i;
  return std::min((i + du) / size(), 1.0 - 1e-16);
}

double PiecewiseConstant1D::pdf(double x) const {
  return pdfOfBin(std::clamp(int(x * size()), 0, size() - 1));
}

PiecewiseConstant2D::PiecewiseConstant2D(const std::vector<double>& f, int nu, int nv) {
  if (nu <= 0 || nv <= 0 || f.size() != std::size_t(nu) * nv)
    throw std::invalid_argument("PiecewiseConstant2D: size mismatch");
  std::vector<double> row_integrals;
  conditional_.reserve(nv);
  for (int v = 0; v < nv; ++v) {
    conditional_.emplace_back(std::vector<double>(f.begin() + std::size_t(v) * nu, f.begin() + std::size_t(v + 1) * nu));
    row_integrals.push_back(conditional_.back().integral());
  }
  marginal_ = PiecewiseConstant1D(std::move(row_integrals));
}

Point2 PiecewiseConstant2D::sample(const Point2& u, double* pdf) const {
  double pdf_v = 0, pdf_u = 0;
  int row = 0;
  const double v = marginal_.sample(u.y(), &pdf_v, &row);
  const double x = conditional_[row].sample(u.x(), &pdf_u);
  *pdf = pdf_v * pdf_u;
  return {x, v};
}

double PiecewiseConstant2D::pdf(const Point2& p) const {
  const int nv = int(conditional_.size());
  const int row = std::clamp(int(p.y() * nv), 0, nv - 1);
  return marginal_.pdfOfBin(row) * conditional_[row].pdf(p.x());
}

}  // namespace vdbappear
