#include "libvdbappear/math/tabulated_phase.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/frame.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace vdbappear {

TabulatedPhase::TabulatedPhase(std::vector<double> values) : values_(std::move(values)) {
  const double k = double(values_.size());
  const double integral = 2 * kPi * std::accumulate(values_.begin(), values_.end(), 0.0) * (2 / k);
  if (values_.empty() || !(integral > 0) || !std::isfinite(integral))
    throw std::invalid_argument("phase table: needs non-negative values that are not all zero");
  normalisation_ = 1 / integral;
  for (double& f : values_) f *= normalisation_;
  mu_distribution_ = PiecewiseConstant1D(values_);
}

double TabulatedPhase::eval(double mu) const {
  const int bin = std::clamp(int((mu + 1) / 2 * bins()), 0, bins() - 1);
  return values_[bin];
}

PhaseSample TabulatedPhase::sample(const Vec3& wi, const Point2& u) const {
  double pdf_x = 0;
  const double mu = std::clamp(2 * mu_distribution_.sample(u.x(), &pdf_x) - 1, -1.0, 1.0);
  const double sin_theta = std::sqrt(std::max(0.0, 1 - mu * mu));
  const double phi = 2 * kPi * u.y();
  const Frame frame = Frame::fromNormal(-wi);
  const Vec3 wo = frame.toWorld(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), mu));
  // pdf over solid angle: pdf_x / 2 per unit mu, / (2 pi) per unit phi; equal to eval(mu).
  return {wo, eval(mu), 1.0};
}

}  // namespace vdbappear
