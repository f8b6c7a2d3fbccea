#pragma once
// The effective BRDF of a surface patch, Eq. (4.6)-(4.8) of the displacement chapter
// (shared/papers/002_6a636dc24396287c.txt, §4.3): the average over the patch of the micro-BRDF
// times <w_m, wi> and the visibility toward the light, weighted by the visible projected area
// toward the viewer. The single-bounce form, from which the scaling function R of Eq. (4.12) is
// the ratio of the original's to the prefiltered model's.

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/surface/microfacet_brdf.h"
#include "libvdbappear/surface/height_field.h"
#include "libvdbappear/surface/tile_edges.h"
#include "libvdbappear/surface/tile_stretch.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace vdbappear {

class SurfaceScene;

// A height field as the renderer sees it (two triangles per cell, surface/height_field_mesh.h):
// points and normals above base positions, and visibility along rays (Embree). Laid out stretched
// by `stretch` (surface/tile_stretch.h: the map's (x, y) to the surface's, heights kept), it is the
// tile as a sphere or a mesh lays it out: points, normals and rays are then the stretched
// surface's, and base positions stay the map's.
//
// `base_curvature` (1 / world units; 0: a plane) lays it on a base that bends away from every point
// as a sphere of radius 1 / base_curvature does, to second order: seen from a point, the surface at
// distance d along the base lies d^2 base_curvature / 2 lower. unoccluded() and trace() follow that
// (what a sphere's bumps shadow and mask, and where a path's next bounce lands).
//
// `edges` (surface/tile_edges.h): the map alone, or as one tile of a periodic surface, whose rays
// leave the tile across one edge and come back across the opposite one.
class MicroGeometry {
 public:
  explicit MicroGeometry(const HeightField& field, const TileStretch& stretch = {}, double base_curvature = 0,
                         TileEdges edges = TileEdges::Open);
  ~MicroGeometry();
  MicroGeometry(const MicroGeometry&) = delete;
  MicroGeometry& operator=(const MicroGeometry&) = delete;

  struct Point {
    Vec3 x;       // on the surface
    Vec3 normal;  // of its triangle, facing +z
    Point2 base;  // the base position on the map, in cell units
  };
  // The surface above base position (u, v), in cell units (0 <= u <= cells x, 0 <= v <= cells y).
  Point at(double u, double v) const;
  // Whether w leaves the point without meeting the surface again (rays beyond an open field escape;
  // over a periodic one they go on through the tiles until they rise above its highest point).
  // On a curved base the ray rises above the map by (t |w_xy|)^2 base_curvature / 2 at t, followed
  // in straight pieces whose chords stray from it by at most a thousandth of the field's relief.
  bool unoccluded(const Point& p, const Vec3& w) const;
  // The first point that a ray from p along w meets, if any (none past an open field's edges; over a
  // periodic one, the point in the tile); over a curved base followed as unoccluded() follows it.
  std::optional<Point> trace(const Point& p, const Vec3& w) const;
  const HeightField& field() const { return field_; }
  const TileStretch& stretch() const { return stretch_; }
  TileEdges edges() const { return edges_; }

 private:
  double rayEpsilon() const;
  Vec3 stretched(const Vec3& on_map) const;
  // How fast a ray along w rises above the map: origin + t w + z bend t^2 (0 on a plane, or straight up).
  double bendOf(const Vec3& w) const { return base_curvature_ * w.head<2>().squaredNorm() / 2; }
  template <typename Visit>
  bool followCurvedRay(const Vec3& origin, const Vec3& w, double eps, Visit&& visit) const;
  // How far a straight ray from x along w goes over a periodic field: until it rises above the
  // field's highest point, or kMostTilesCrossed tiles (longestPeriodicRay()).
  double periodicReach(const Vec3& x, const Vec3& w) const;
  double longestPeriodicRay() const;
  // The straight piece x + t d, t in [t_min, t_max], d a unit vector, x in the tile: visit(a, d,
  // t0, t1) for it, or over a periodic field for each part of it within one tile, a that part's
  // start moved into the tile, until visit returns true (then this does); x is left at the piece's
  // end, moved into the tile.
  template <typename Visit>
  bool walkPiece(Vec3& x, const Vec3& d, double t_min, double t_max, Visit&& visit) const;
  // How far x travels along d (d_map: d's (x, y) on the map) before it leaves the tile, and across
  // which edge: axis 0 or 1.
  double tileExit(const Vec3& x, const Eigen::Vector2d& d_map, int& axis) const;
  Point pointOf(const Vec3& x, const Vec3& normal) const;  // a point of the stretched surface
  HeightField field_;
  TileStretch stretch_;
  double base_curvature_;
  TileEdges edges_;
  double highest_;  // the field's highest point
  // How far a curved ray's chords may stray from it: a fraction of the field's relief, the same for a
  // map and its h_low whatever their cells (a tenth of a cell, as first, let h_low's rays at 32x
  // pass 10% of a bump's height higher than the original's, and so shadow and mask it less).
  static constexpr double kChordSagOfRelief = 1e-3;
  double chord_sag_;
  Eigen::Vector2d lo_, hi_;  // the box of the surface's (x, y)
  Eigen::Vector2d tile_;     // the tile's width and depth on the map (world units)
  // A ray over a periodic field that has not risen above it after this many tiles' widths is taken
  // to escape: it skims the tops of the tiles (a direction of measure zero, as w.z -> 0).
  static constexpr double kMostTilesCrossed = 256;
  std::unique_ptr<SurfaceScene> scene_;
};

// f(point, normal, wi, wo), the BRDF at a micro-surface point; directions in the base frame.
using PatchBrdf = std::function<Rgb(const Vec3& x, const Vec3& normal, const Vec3& wi, const Vec3& wo)>;

// The same microfacet BRDF everywhere, in the frame of each micro-normal (f_orig of §4.3).
PatchBrdf microfacetPatchBrdf(const MicrofacetBrdf& base);

struct EffectiveBrdfSettings {
  int samples_per_side = 50;  // stratified base positions: 2500, the chapter's paths per estimate (§4.7.1)
  std::uint64_t seed = 1;     // the jitter's stream, keyed by the patch
  bool visibility = true;     // V of Eq. (4.6)-(4.7); off only as a negative control in tests
};

struct EffectiveBrdf {
  Rgb value = Rgb::Zero();   // f_eff(wi, wo) of Eq. (4.6)
  double visible_area = 0;   // A_G(wo) of Eq. (4.8), estimated from the same samples
};

// Over the count x count cells from cell (i0, j0): the estimate of Eq. (4.6), the ratio of the
// integral of f <w_m, wi> V(wi) A_G(p, wo) to that of A_G(p, wo) over base positions p.
EffectiveBrdf effectiveBrdf(const MicroGeometry& geometry, int i0, int j0, int count, const PatchBrdf& f,
                            const Vec3& wi, const Vec3& wo, const EffectiveBrdfSettings& settings);

// The frame of Eq. (4.6) and (4.17) for any reflectance r(x, wi, wo) of the points seen along wo:
// the ratio of the integrals of r A_G(p, wo) and of A_G(p, wo) over samples_per_side^2 jittered
// base positions p, drawn from a stream keyed by the patch. `r(point, a, b)` is called for the
// visible points, (a, b) the position's stratum.
using PointReflectance = std::function<Rgb(const MicroGeometry::Point& x, int a, int b)>;
EffectiveBrdf visibleAreaAverage(const MicroGeometry& geometry, int i0, int j0, int count, const Vec3& wo,
                                 const EffectiveBrdfSettings& settings, const PointReflectance& r);

// The same for `n` reflectances at once, over the same positions: `r(point, a, b, values)` writes
// values[0 .. n); the result holds one average per reflectance, each with the same visible area.
using PointReflectances = std::function<void(const MicroGeometry::Point& x, int a, int b, Rgb* values)>;
std::vector<EffectiveBrdf> visibleAreaAverages(const MicroGeometry& geometry, int i0, int j0, int count, const Vec3& wo,
                                               const EffectiveBrdfSettings& settings, std::size_t n,
                                               const PointReflectances& r);

// effectiveBrdf() for many light directions at once: out[k] for wis[k], from the same positions
// (each equal to effectiveBrdf() of wis[k] alone, whose positions do not depend on wi).
std::vector<EffectiveBrdf> effectiveBrdfs(const MicroGeometry& geometry, int i0, int j0, int count, const PatchBrdf& f,
                                          const std::vector<Vec3>& wis, const Vec3& wo,
                                          const EffectiveBrdfSettings& settings);

}  // namespace vdbappear
