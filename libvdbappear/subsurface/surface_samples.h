#pragma once
// Where pass 1 samples the irradiance (§3.4 of the translucent-caching seed): at the centroid of
// each face, with the face's area. The seed subdivides a mesh that is too coarse by hand; here
// faces are split until no edge is longer than a given length.

#include "libvdbappear/math/triangle.h"

#include <vector>

namespace vdbappear {

struct SurfacePoint {
  Vec3 p;       // centroid
  Vec3 normal;  // unit, counter-clockwise (outward on outwardClosedMesh's triangles)
  double area = 0;
  Triangle face;  // the piece itself
};

// Each triangle halved across its longest edge until every edge is at most max_edge, then one
// point per piece. The pieces tile the surface (T-junctions do not matter to area sums).
std::vector<SurfacePoint> surfacePoints(const std::vector<Triangle>& triangles, double max_edge);

}  // namespace vdbappear
