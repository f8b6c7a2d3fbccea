#pragma once
// The factorised scaling function of Eq. (4.21) in the displacement chapter
// (shared/papers/002_6a636dc24396287c.txt, §4.6): R_ir(x, wi, wo) ~ T_ir(x) S_ir(wi, wo), a 2-D
// spatial table over the whole map and a 4-D angular table over the concentric-mapped hemisphere
// of each direction (math/concentric_mapping.h). Both are read between bin centres (bi- and
// quadrilinear), clamped at the edges. The tables are filled by prefilter/scaling_factorization.h.

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/vector.h"

#include <cstddef>

#include <vector>

namespace vdbappear {

// T_ir(x) on M x M bins over the map's base square [0,1]^2; averages one (§4.7.1).
struct SpatialScaling {
  int resolution = 1;        // M
  std::vector<Rgb> values;   // bin (a, b) at a + M b; a along x
  Rgb operator()(const Point2& x) const;
  Point2 binCentre(int a, int b) const;
};

// S_ir(wi, wo) on N^2 bins of the concentric square of wi times N^2 of wo; directions in the
// macro-surface's frame (n = +z).
struct AngularScaling {
  int resolution = 1;        // N
  std::vector<Rgb> values;   // bin (wi bin (ia, ib), wo bin (oa, ob)) at index(ia, ib, oa, ob)
  Rgb operator()(const Vec3& wi, const Vec3& wo) const;
  std::size_t index(int ia, int ib, int oa, int ob) const {
    const std::size_t N = resolution;
    return ((std::size_t(ib) * N + ia) * N + ob) * N + oa;
  }
  Vec3 binDirection(int a, int b) const;  // the direction at a bin's centre
};

struct FactorizedScaling {
  SpatialScaling T;
  AngularScaling S;
  Rgb operator()(const Point2& x, const Vec3& wi, const Vec3& wo) const { return T(x) * S(wi, wo); }  // Eq. (4.21)
};

}  // namespace vdbappear
