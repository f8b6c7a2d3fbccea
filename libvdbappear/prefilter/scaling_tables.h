#pragma once
// The factorised scaling function of Eq. (4.21) in the displacement chapter
// (shared/papers/002_6a636dc24396287c.txt, §4.6): R_ir(x, wi, wo) ~ T_ir(x) S_ir(wi, wo), a 2-D
// spatial table over the whole map and a 4-D angular table over the concentric-mapped hemisphere
// of each direction (math/concentric_mapping.h). Both are read between bin centres (bi- and
// quadrilinear), clamped at the edges. The tables are filled by prefilter/scaling_factorization.h.

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/vector.h"
#include "libvdbappear/surface/cell_relief.h"

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
//
// With view_horizon, wo has N + 2 nodes along each axis of its square: the N bin centres and the
// square's two edges, where wo lies on the horizon (docs/displacement.md §6, "The view's horizon").
// Beyond the outermost bin centres (83 degrees at N = 15) S is then read toward its value at the
// horizon instead of clamped: grazing views, which Eq. (4.5) weighs by alpha_k alone, not by the
// visible projected area <mu_k, wo> / cos theta_o that the original shows them.
//
// With relief_slopes, the relief term's B(wi, wo) on the same nodes (docs/displacement.md §6, "The
// relief term"): R is then T(x) [S(wi, wo) + B(wi, wo) z(x)], z h_low's CellRelief, and `values`
// hold R's intercept at z = 0.
struct AngularScaling {
  int resolution = 1;         // N
  bool view_horizon = false;  // wo's edge nodes
  std::vector<Rgb> values;    // (wi bin (ia, ib), wo node (oa, ob)) at index(ia, ib, oa, ob)
  std::vector<Rgb> relief_slopes;  // B at the same indices; empty: none
  Rgb operator()(const Vec3& wi, const Vec3& wo) const { return read(wi, wo, nullptr); }
  // S(wi, wo), and into *slope B(wi, wo) from the same interpolation weights (one set of them per
  // shading point); relief_slopes must be filled.
  Rgb withReliefSlope(const Vec3& wi, const Vec3& wo, Rgb* slope) const { return read(wi, wo, slope); }
  int viewNodes() const { return view_horizon ? resolution + 2 : resolution; }  // per axis of wo's square
  std::size_t index(int ia, int ib, int oa, int ob) const {
    const std::size_t N = resolution, V = viewNodes();
    return ((std::size_t(ib) * N + ia) * V + ob) * V + oa;
  }
  Vec3 binDirection(int a, int b) const;  // the direction at a bin's centre
  // wo's node (oa, ob): a bin centre, or with view_horizon on the horizon where oa or ob is an edge
  // (0 or N + 1; bin k is node k + 1).
  bool onHorizon(int oa, int ob) const {
    const int edge = resolution + 1;
    return view_horizon && (oa == 0 || ob == 0 || oa == edge || ob == edge);
  }
  Vec3 viewNodeDirection(int oa, int ob) const;

 private:
  // values quadrilinearly, and with `slope` relief_slopes at the same weights.
  Rgb read(const Vec3& wi, const Vec3& wo, Rgb* slope) const;
};

// Eq. (4.21), R ~ T(x) S(wi, wo); with the relief term (S.relief_slopes and `relief` of h_low)
// R ~ T(x) [S(wi, wo) + B(wi, wo) z(x)], not below 0.
struct FactorizedScaling {
  SpatialScaling T;
  AngularScaling S;
  CellRelief relief;  // z of h_low's cells, with S.relief_slopes
  // The relative standard error of each S bin's estimate (at S.values' indices), how far the
  // table's draw may lie from the bin's true ratio: what the sampling rates buy
  // (docs/displacement.md §6, "The tables' own error"). Filled by factorizeScaling(); not in the
  // files (empty when read).
  std::vector<double> S_relative_errors;
  Rgb operator()(const Point2& x, const Vec3& wi, const Vec3& wo) const {
    if (S.relief_slopes.empty() || relief.empty()) return T(x) * S(wi, wo);
    Rgb B;
    const Rgb intercept = S.withReliefSlope(wi, wo, &B);
    return T(x) * (intercept + B * relief(x)).max(0.0);
  }
};

}  // namespace vdbappear
