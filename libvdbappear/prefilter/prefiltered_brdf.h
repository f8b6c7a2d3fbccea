#pragma once
// The prefiltered SVBRDF of the displacement chapter (shared/papers/002_6a636dc24396287c.txt):
//   f_low(x, wi, wo) = T(x) S(wi, wo) f'_low(x, wi, wo)        (Eq. 4.13, 4.18 with R of Eq. 4.21),
// f'_low the multi-lobe BRDF of the coarse cell under x (Eq. 4.11), directions in the map's base
// frame (n = +z), wi toward the light and wo toward the viewer. What vdb_render shades a
// prefiltered displacement map with; sampling follows f'_low.

#include "libvdbappear/prefilter/displacement_prefilter.h"
#include "libvdbappear/surface/multi_lobe_brdf.h"

#include <vector>

namespace vdbappear {

class PrefilteredBrdf {
 public:
  // kPlane keeps Eq. (4.5)'s cut at the base horizon: on a plane only a finite patch's edges see
  // below it, and there the light continued from the horizon came out high (the white furnace of
  // docs/displacement.md §8 1.016 against 0.997; the planar maps under the sky 0.06-0.48 points
  // brighter). kCurved, for a shell over a sphere, shades below the horizon as described below.
  enum class Base { kPlane, kCurved };

  PrefilteredBrdf(const PrefilteredSurface& surface, const MicrofacetBrdf& base, Base shape);

  // The share of sample()'s directions drawn below the base horizon.
  static constexpr double kBelowHorizonShare = 1.0 / 16;

  // x: the base position on the map, in [0,1]^2 (clamped). On a curved base, directions below the
  // base horizon, which a shell over a sphere shows beyond its terminator and at its silhouette,
  // are not cut off as Eq. (4.5) on a plane may: f'_low's lobes reach there as far as their facets
  // tilt (MultiLobeBrdf::projected over the limited cos theta_i of the horizon), and S is read at
  // the horizon. On a plane the map itself shadows and masks them. Only the lights' own light
  // counts there (render/volume_path_tracer.cpp, Vertex::reflectsBack; docs/displacement.md §8).
  //
  // `stretch`: how the surface lays the tile out where x lies (surface/tile_stretch.h; a sphere's
  // tiles narrow toward its poles), and `coarse_normal` the normal of h_low's facet there (base
  // frame, either side). The model is then the map's at the mapped directions
  // vi = stretch.toMap(wi), vo = stretch.toMap(wo), each fine lobe weighed and the coarse facet's
  // weight divided out, as tile_stretch.h derives:
  //   f_low = T(x) S(vi, vo) MultiLobeBrdf::projected(wi, wo, stretch) / cos theta(vi) / |A^T n_c|,
  // 1 / cos theta(vi) = |A^-1 wi| / cos theta_i limited as MultiLobeBrdf limits 1 / cos theta_i.
  // T S are the tables made for the tile nearest the stretch (the square's, or one of
  // PrefilteredSurface::stretched), read at the directions mapped from the surface to that tile;
  // between two tables, both blended (scalingOnTile). With the square's alone: only f'_low's facets
  // are weighed, and S and T read at the mapped directions keep what shadows and masks what
  // (docs/displacement.md §8).
  Rgb eval(const Point2& x, const Vec3& wi, const Vec3& wo, const TileStretch& stretch = {},
           const Vec3& coarse_normal = Vec3::UnitZ()) const;
  // wi by f'_low's lobes (of the square tile whatever the stretch). On a plane a draw below the base
  // horizon, where Eq. (4.5) is zero, is mirrored above it (its density then the sum of the two
  // draws'), so that no draw is lost; on a curved base with probability kBelowHorizonShare a draw
  // above is mirrored below the horizon. weight = eval |cos theta_i| / pdf.
  BrdfSample sample(const Point2& x, const Vec3& wo, double u_lobe, const Point2& u, const TileStretch& stretch = {},
                    const Vec3& coarse_normal = Vec3::UnitZ()) const;
  double pdf(const Point2& x, const Vec3& wo, const Vec3& wi) const;  // solid-angle density of sample()

  // T(x) S of the tables for a tile stretched by `stretch`, wi and wo the surface's: each table k
  // made for A_k is read at R_k.toMap(w), R_k = A A_k^-1 the stretch left from its tile to this one.
  // The nearest two tables by d_k = |R_k - I| + |R_k^-1 - I| (Frobenius) are blended with weights
  // 1 / d_k - 1 / d_3, d_3 the third nearest's distance (0 without one), so that a table's own
  // stretch reads that table alone and the blend changes continuously with the stretch.
  Rgb scalingOnTile(const Point2& x, const Vec3& wi, const Vec3& wo, const TileStretch& stretch) const;

 private:
  const MultiLobeBrdf& cellAt(const Point2& x) const;

  std::vector<MultiLobeBrdf> cells_;  // cell (u, v) at u + cells_x v
  int cells_x_, cells_y_;
  // T S of the square tile's tables.
  Rgb square(const Point2& x, const Vec3& wi, const Vec3& wo) const { return tables_.front().scaling(x, wi, wo); }

  Base shape_;
  std::vector<StretchedScaling> tables_;  // the square tile's first, then the stretched tiles'
};

}  // namespace vdbappear
