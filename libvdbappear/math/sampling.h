#pragma once
// Warps from [0,1)^2 to directions (and normal numbers), and the multiple-importance-sampling heuristic
// (pbrt-v4, Ch. 2 and A.5). Each warp sits next to its pdf.

#include "libvdbappear/math/concentric_mapping.h"
#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/vector.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

inline Vec3 sampleUniformSphere(const Point2& u) {
  const double z = 1 - 2 * u.x();
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  const double phi = 2 * kPi * u.y();
  return {r * std::cos(phi), r * std::sin(phi), z};
}
inline constexpr double uniformSpherePdf() { return 1 / (4 * kPi); }

// Cosine-weighted hemisphere around +z (Malley's method on the concentric disk).
inline Vec3 sampleCosineHemisphere(const Point2& u) {
  const Point2 d = squareToConcentricDisk(u);
  return {d.x(), d.y(), std::sqrt(std::max(0.0, 1 - d.x() * d.x() - d.y() * d.y()))};
}
inline double cosineHemispherePdf(double cos_theta) { return std::max(0.0, cos_theta) / kPi; }

// Uniform point on a triangle (Heitz 2019, "A Low-Distortion Map Between Triangle and Square"):
// barycentric weights (b0, b1) of the first two vertices.
inline Point2 sampleUniformTriangle(const Point2& u) {
  double b0, b1;
  if (u.x() < u.y()) {
    b0 = u.x() / 2;
    b1 = u.y() - b0;
  } else {
    b1 = u.y() / 2;
    b0 = u.x() - b1;
  }
  return {b0, b1};
}

// Two independent standard normal numbers (Box-Muller). u in [0,1)^2.
inline Point2 sampleStandardNormalPair(const Point2& u) {
  const double r = std::sqrt(-2 * std::log(1 - u.x())), phi = 2 * kPi * u.y();
  return {r * std::cos(phi), r * std::sin(phi)};
}

// Veach's power heuristic with beta = 2, for one sample of each strategy.
inline double powerHeuristic(double pdf_f, double pdf_g) {
  const double f = pdf_f * pdf_f, g = pdf_g * pdf_g;
  if (std::isinf(f)) return 1;
  return f + g > 0 ? f / (f + g) : 0;
}

}  // namespace vdbappear
