#pragma once
// How a shell lays a tile of a displacement map onto a surface where the tile is not the square it
// was prefiltered as: the map's base plane goes to the surface's tangent plane by a linear map
// (a 2 x 2 matrix M over the base frame's x and y, M = diag(cos latitude, 1) on a sphere of
// latitude-longitude tiles) and heights stay as they are, so that space is mapped by
// A = [[M, 0], [0, 1]] (docs/displacement.md §8, "Stretched tiles").
//
// A linear map of space keeps what shadows and masks what: a ray along w over the stretched surface
// meets what a ray along A^-1 w meets over the map. A facet of normal m becomes one of normal
// A^-T m, and its area and its projected area toward w change by |A^-T m| det A and by
// |A^-1 w| det A. Put into Eq. (4.6) of the displacement chapter, the stretched surface's effective
// BRDF is the map's at the mapped directions, with each facet's share weighed by 1 / |A^-T m|:
//   f_eff'(wi, wo) = 1 / (cos theta_i cos theta_o) int f(m'; wi, wo) <m, vi> <m, vo> V / |A^-T m| dA,
// vi = toMap(wi), vo = toMap(wo), cosines and V of the map at vi and vo, m' = normalOnSurface(m),
// the base BRDF f at the stretched facet. Exact; tests/unit/tile_stretch_test.cpp checks it against
// a map sampled stretched. The same holds for h_low: a coarse facet of normal m_c that the model
// shades with f_low counts 1 / |A^-T m_c| as much once stretched, so a prefiltered model divides
// f_low by that weight to stay the fine facets' sum (prefilter/prefiltered_brdf.h).

#include "libvdbappear/math/vector.h"

namespace vdbappear {

class TileStretch {
 public:
  TileStretch() = default;  // the identity: a square tile of the map's own size
  // m: the map's (x, y) to the surface's, per unit; invertible.
  explicit TileStretch(const Eigen::Matrix2d& m) : m_(m), identity_(m == Eigen::Matrix2d::Identity()) {
    inverse_ << m(1, 1), -m(0, 1), -m(1, 0), m(0, 0);
    inverse_ /= m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
  }
  static TileStretch diagonal(double x, double y) { return TileStretch((Eigen::Matrix2d() << x, 0, 0, y).finished()); }

  const Eigen::Matrix2d& matrix() const { return m_; }
  const Eigen::Matrix2d& inverse() const { return inverse_; }
  bool isIdentity() const { return identity_; }

  // A^-1 w normalised: the direction over the map that sees what w sees over the surface.
  Vec3 toMap(const Vec3& w) const {
    const Eigen::Vector2d xy = inverse_ * w.head<2>();
    return Vec3(xy.x(), xy.y(), w.z()).normalized();
  }
  // A^-T m, the map's micro-normal m as it stands on the surface, unnormalised: its length is
  // 1 / facetWeight(m).
  Vec3 normalOnSurfaceUnnormalised(const Vec3& normal) const {
    const Eigen::Vector2d xy = inverse_.transpose() * normal.head<2>();
    return Vec3(xy.x(), xy.y(), normal.z());
  }
  Vec3 normalOnSurface(const Vec3& normal) const { return normalOnSurfaceUnnormalised(normal).normalized(); }
  // 1 / |A^-T m| for a unit m: how much less a facet counts on the surface than on the map.
  double facetWeight(const Vec3& normal) const { return 1 / normalOnSurfaceUnnormalised(normal).norm(); }
  // The same weight from the facet's unit normal n on the surface: |A^T n| (A^T n / |A^T n| is the
  // map's facet).
  double facetWeightOnSurface(const Vec3& n) const {
    const Eigen::Vector2d xy = m_.transpose() * n.head<2>();
    return Vec3(xy.x(), xy.y(), n.z()).norm();
  }

 private:
  Eigen::Matrix2d m_ = Eigen::Matrix2d::Identity(), inverse_ = Eigen::Matrix2d::Identity();
  bool identity_ = true;
};

}  // namespace vdbappear
