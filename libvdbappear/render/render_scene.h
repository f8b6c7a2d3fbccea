#pragma once
// Everything a path sees: an optional medium, the lights, the opaque surfaces.

#include "libvdbappear/lightgrid/cell_interpolation.h"
#include "libvdbappear/medium/lobe_weight_scales.h"
#include "libvdbappear/medium/medium_view.h"
#include "libvdbappear/render/level_of_detail.h"
#include "libvdbappear/render/light.h"
#include "libvdbappear/render/surface_scene.h"
#include "libvdbappear/surface/microfacet_brdf.h"
#include "libvdbappear/surface/mesh_shell.h"
#include "libvdbappear/surface/sphere_shell.h"

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vdbappear {

class PrefilteredBrdf;
class ShGridLookup;
class TranslucentObject;

// A prefiltered displacement map as placed in the scene: its SVBRDF and where its tiles lie, on a
// plane, or shell-mapped over a sphere or over a mesh by its UVs.
struct PrefilteredPlacement {
  std::shared_ptr<const PrefilteredBrdf> brdf;
  Vec3 origin = Vec3::Zero();  // vertex (0, 0) of the first tile at height 0
  double size = 1;             // of one tile along x and y
  std::optional<SphereShell> shell;  // instead of the plane through origin
  std::shared_ptr<const MeshShell> mesh;  // instead of the plane or the sphere; its triangles are the surface's
  // Where world point p, the hit `hit` of this surface, lies on the map: the base position in [0,1)^2
  // of the tile under it, and the map's base frame (x, y, height) in world directions there (the
  // world's axes on the plane). On a plane or a sphere p alone says it; on a mesh the hit's triangle.
  // On a sphere or a mesh, also how the tile there is stretched against the square of `size` that the
  // map was prefiltered as (surface/tile_stretch.h): toward a sphere's poles, and wherever a mesh's
  // UVs do not lay tiles out square and `size` wide.
  struct MapPoint {
    Point2 position;
    Frame frame;
    TileStretch stretch;
  };
  MapPoint mapPoint(const Vec3& p, const SurfaceHit& hit = {}) const {
    if (mesh) {
      const MeshShell::MapPoint at = mesh->mapPoint(hit.primitive, hit.barycentric);
      return {fractional(at.tile), at.frame, TileStretch(at.tile_to_frame / size)};
    }
    const Point2 uv = shell ? shell->tileCoordinates(p) : Point2((p.x() - origin.x()) / size, (p.y() - origin.y()) / size);
    if (!shell) return {fractional(uv), {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()}, {}};
    return {fractional(uv), shell->frame(uv.x(), uv.y()), shell->stretch(uv.y())};
  }
  static Point2 fractional(const Point2& tile) { return {tile.x() - std::floor(tile.x()), tile.y() - std::floor(tile.y())}; }
};

struct RenderScene {
  std::shared_ptr<const MediumView> medium;      // may be null: surfaces only
  // Optional factors on the medium's lobe weights per (cluster, slot): how the weight optimisation
  // renders candidate weight factors without rewriting the medium.
  std::shared_ptr<const LobeWeightScales> lobe_scales;
  std::vector<std::unique_ptr<Light>> lights;    // area lights too; SurfaceHit::light indexes this
  std::unique_ptr<SurfaceScene> surfaces;        // may be null or empty
  std::vector<MicrofacetBrdf> brdfs;             // of the glossy surfaces; SurfaceHit::brdf indexes this
  std::vector<PrefilteredPlacement> prefiltered; // SurfaceHit::prefiltered indexes this
  // Mipmaps of prefiltered maps (§4.7.2): each path's level of detail comes from its camera ray's
  // footprint on them (render/level_of_detail.h); their levels are surfaces of those levels.
  std::vector<MipmapFootprint> mipmaps;
  // Closed meshes whose light leaves by the dipole (subsurface/); SurfaceHit::translucent indexes this.
  std::vector<std::shared_ptr<TranslucentObject>> translucent;  // read-only while rendering
  double ray_epsilon = 1e-5;                     // offset of rays leaving surfaces (world units)
  // Optional: the area lights' direct light from an SH light grid (dissertation ch. 5) at vertices
  // inside its box, instead of next-event estimation of every area light; outside the box the lights
  // are sampled. The area lights stay visible to camera rays.
  std::shared_ptr<const ShGridLookup> sh_lights;
  CellInterpolation sh_interpolation = CellInterpolation::kHermite;
  // Attenuate the grid's light at each vertex by the medium's transmittance along one ray: toward the
  // grid's dominant direction there, or along the sampled direction where one is sampled (one
  // ratio-tracking ray, not one per light; docs/sh_lightgrid.md §5).
  bool sh_shadows = true;
  // What building the scene decided for the user (a line each, for -v), and what may not be what
  // they meant (a line each, always shown): e.g. a prefiltered map stretched over a mesh.
  std::vector<std::string> notes, warnings;
};

}  // namespace vdbappear
