#pragma once
// Shirley and Chiu's concentric map between the square and the disk ("A Low Distortion Map Between
// Disk and Square", 1997; reference [87] of the displacement chapter), both ways, and the
// equal-area hemisphere over it: z = 1 - r^2, so equal areas of the square are equal solid angles.
// The angular tables of the scaling function (Eq. 4.21, §4.6) are regular grids on this square.

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/vector.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

// u in [0,1]^2 to the unit disk.
inline Point2 squareToConcentricDisk(const Point2& u) {
  const double a = 2 * u.x() - 1, b = 2 * u.y() - 1;
  if (a == 0 && b == 0) return {0, 0};
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = kPi / 4 * (b / a);
  } else {
    r = b;
    phi = kPi / 2 - kPi / 4 * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

// The inverse: the unit disk to [0,1]^2.
inline Point2 concentricDiskToSquare(const Point2& d) {
  const double r = std::hypot(d.x(), d.y());
  double phi = std::atan2(d.y(), d.x());
  if (phi < -kPi / 4) phi += 2 * kPi;  // phi in [-pi/4, 7 pi/4): the four wedges in order
  double a, b;
  if (phi < kPi / 4) {
    a = r;
    b = phi * a / (kPi / 4);
  } else if (phi < 3 * kPi / 4) {
    b = r;
    a = -(phi - kPi / 2) * b / (kPi / 4);
  } else if (phi < 5 * kPi / 4) {
    a = -r;
    b = (phi - kPi) * a / (kPi / 4);
  } else {
    b = -r;
    a = -(phi - 3 * kPi / 2) * b / (kPi / 4);
  }
  return {(a + 1) / 2, (b + 1) / 2};
}

// [0,1]^2 to the upper hemisphere (z >= 0), area-preserving up to the factor 2 pi.
inline Vec3 squareToHemisphere(const Point2& u) {
  const Point2 d = squareToConcentricDisk(u);
  const double r2 = std::min(1.0, d.squaredNorm()), scale = std::sqrt(2 - r2);
  return {d.x() * scale, d.y() * scale, 1 - r2};
}

// The inverse, for w with z >= 0 (unit length).
inline Point2 hemisphereToSquare(const Vec3& w) {
  const double scale = 1 / std::sqrt(1 + std::max(0.0, w.z()));
  return concentricDiskToSquare({w.x() * scale, w.y() * scale});
}

}  // namespace vdbappear
