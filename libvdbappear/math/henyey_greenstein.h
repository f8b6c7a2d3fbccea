#pragma once
// The Henyey-Greenstein phase function (pbrt-v4 §11.3.1), in the project's convention: wi and wo
// both point away from the scattering point, so the cosine of the scattering angle is
// mu = -wi . wo, and g > 0 scatters forward.

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/frame.h"
#include "libvdbappear/math/sggx.h"  // PhaseSample

#include <cmath>

namespace vdbappear {

// p(mu) = (1 - g^2) / (4 pi (1 + g^2 - 2 g mu)^(3/2)).
inline double henyeyGreenstein(double mu, double g) {
  const double denom = 1 + g * g - 2 * g * mu;
  return (1 - g * g) / (4 * kPi * denom * std::sqrt(std::max(denom, 1e-300)));
}

inline double henyeyGreensteinPhase(const Vec3& wi, const Vec3& wo, double g) { return henyeyGreenstein(-wi.dot(wo), g); }

// Below this |g| sampleHenyeyGreenstein draws mu uniformly.
inline constexpr double kHenyeyGreensteinUniformBelow = 1e-5;

// Inverts the CDF of mu; phi uniform. pdf = phase, weight 1. For |g| < 1e-5 the inversion
// cancels badly: mu is then uniform, with pdf 1/(4 pi) and weight phase / pdf.
inline PhaseSample sampleHenyeyGreenstein(const Vec3& wi, double g, const Point2& u) {
  double mu;
  const bool uniform = std::abs(g) < kHenyeyGreensteinUniformBelow;
  if (uniform) {
    mu = 1 - 2 * u.x();
  } else {
    const double s = (1 - g * g) / (1 + g - 2 * g * u.x());
    mu = (1 + g * g - s * s) / (2 * g);
  }
  mu = std::clamp(mu, -1.0, 1.0);
  const double sin_theta = std::sqrt(std::max(0.0, 1 - mu * mu));
  const double phi = 2 * kPi * u.y();
  const Frame frame = Frame::fromNormal(-wi);  // around the direction of propagation
  const Vec3 wo = frame.toWorld(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), mu));
  if (uniform) return {wo, 1 / (4 * kPi), 4 * kPi * henyeyGreenstein(mu, g)};
  return {wo, henyeyGreenstein(mu, g), 1.0};
}

}  // namespace vdbappear
