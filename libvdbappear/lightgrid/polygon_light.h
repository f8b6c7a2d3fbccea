#pragma once
// A uniform polygonal area light (dissertation ch. 5): planar, simple, with RGB radiance. It emits
// toward the side of its counter-clockwise normal (p1 - p0) x (p2 - p0) (Newell's normal for more
// vertices), or to both sides when two-sided.

#include "libvdbappear/math/vector.h"

#include <string>
#include <vector>

namespace vdbappear {

struct PolygonLight {
  std::vector<Vec3> vertices;
  Vec3 radiance = Vec3(1, 1, 1);
  bool two_sided = false;

  Vec3 normal() const;  // unit, counter-clockwise (Newell)
  double area() const;
};

// Throws std::invalid_argument naming `what` when the polygon has fewer than 3 vertices, repeated
// or non-finite vertices, zero area, vertices off its plane, or negative/non-finite radiance.
void validatePolygonLight(const PolygonLight& light, const std::string& what);

// The vertices as Algorithm 2 wants them seen from x: ordered so that the face normal points away
// from x ((p1 - p0) x (p2 - p0) . (p0 - x) > 0). Empty when x does not see the emitting side or
// lies in the light's plane (to within 1e-12 of the distances involved).
std::vector<Vec3> verticesFacing(const PolygonLight& light, const Vec3& x);

}  // namespace vdbappear
