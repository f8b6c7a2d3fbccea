#pragma once
// Orthonormal frames around a unit vector.

#include "libvdbappear/math/vector.h"

#include <cmath>

namespace vdbappear {

// A right-handed orthonormal basis (s, t, n) with n given.
struct Frame {
  Vec3 s, t, n;

  // Duff, Burgess, Christensen, Hery, Kensler, Liani, Villemin 2017,
  // "Building an Orthonormal Basis, Revisited" (robust everywhere, n.z = -1 included).
  static Frame fromNormal(const Vec3& n) {
    const double sign = std::copysign(1.0, n.z());
    const double a = -1.0 / (sign + n.z());
    const double b = n.x() * n.y() * a;
    return {Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x()),
            Vec3(b, sign + n.y() * n.y() * a, -n.y()), n};
  }

  Vec3 toLocal(const Vec3& v) const { return {v.dot(s), v.dot(t), v.dot(n)}; }
  Vec3 toWorld(const Vec3& v) const { return v.x() * s + v.y() * t + v.z() * n; }
};

// Specular reflection of w about the unit normal m (both pointing away from the surface point).
inline Vec3 reflect(const Vec3& w, const Vec3& m) { return 2.0 * w.dot(m) * m - w; }

}  // namespace vdbappear
