#pragma once
// Level of detail for mipmaps of prefiltered displacement maps (§4.7.2, dissertation ch. 4): each
// camera ray's pixel footprint on the map's base (a plane, a sphere or a mesh), in cells of the
// original map, picks the two levels whose downsampling factors bracket it, and the path is traced
// on one of them, the coarser with probability equal to the linear interpolation weight (in log
// factor). Over many paths this is the chapter's linear interpolation of the two levels' path
// contributions, at the cost of one path instead of two. The whole path sees that one level
// (render/surface_scene.h, DetailLevels). Levels are matched by index: in a scene of several
// mipmaps, level k is each one's k-th (or its last). Queries outside the path tracer (the visible
// points of render/visible_points.h, pass 1 of translucent objects) see level 0.

#include "libvdbappear/render/ray.h"

#include <functional>
#include <optional>
#include <vector>

namespace vdbappear {

class MeshShell;
class RandomStream;
struct SphereShell;

// Where a camera ray meets the curved base of a mipmap's tiles (a sphere, a mesh): the distance, the
// cosine between the ray and the base's normal there, and the world width of one cell of the
// original map there (the square root of its area, which the base stretches).
struct BaseHit {
  double t = 0, cos_theta = 1, cell = 1;
};
using BaseIntersector = std::function<std::optional<BaseHit>(const Ray&)>;

// Which width of a pixel's footprint picks the levels. §4.7.2 computes the footprint from ray
// differentials and does not say which of its widths picks the levels. The footprint of a ray that
// meets the base at theta from its normal is, to first order, t spread across the view and t spread /
// cos(theta) along it. `narrow` takes the width across, the pixel's finest extent, so that a grazing
// view does not get the coarse levels that its length along the view would pick (the pixel's samples
// cover its length, as anisotropic texture filtering's probes do); `area` takes the square root of
// its area, t spread / sqrt(cos(theta)), coarser toward the horizon (docs/displacement.md §8-9).
enum class FootprintWidth { narrow, area };

// A mipmap as the renderer places it: tiles on the plane z = origin.z from origin.xy, or on a curved
// base.
struct MipmapFootprint {
  Vec3 origin = Vec3::Zero();
  double width_x = 1, width_y = 1;  // all tiles together, world units
  double cell = 1;                  // world width of one cell of the original map
  std::vector<double> factors;      // of levels 0, 1, ...: increasing, 1 for the original map
  BaseIntersector curved;           // set: the tiles lie on it (origin, widths and cell unused)
  FootprintWidth levels_by = FootprintWidth::narrow;  // which width of a pixel's footprint picks the levels
};

// The bases of surface/sphere_shell.h and surface/mesh_shell.h for an original map of cells_x x
// cells_y cells per tile. Over a sphere a cell is (2 pi r cos(latitude) / (tiles_x cells_x)) by
// (pi r / (tiles_y cells_y)); over a mesh each triangle's cells share its area by its part of the
// UV square (the mesh's base triangles are kept in an Embree scene of their own).
BaseIntersector sphereBase(const SphereShell& shell, int cells_x, int cells_y);
BaseIntersector meshBase(const MeshShell& shell, int cells_x, int cells_y);

// Levels `lower` and `upper` = lower + 1 (or both the same), upper with weight `weight`.
struct LevelBlend {
  int lower = 0, upper = 0;
  double weight = 0;
};

// The footprint's width in original cells between factors F_k <= n < F_k+1 gives w =
// log(n / F_k) / log(F_k+1 / F_k); below the finest factor the finest level, beyond the coarsest the
// coarsest.
LevelBlend blendForFootprint(const std::vector<double>& factors, double footprint_cells);

// A camera ray's pixel footprint where it meets the mipmap's base plane inside its tiles (or its
// curved base): the distance t there, and the footprint's widths in original cells, across the view
// (t spread) and as the square root of its area (t spread / sqrt(cos theta)); nothing if it misses.
struct Footprint {
  double t = 0, narrow_cells = 0, area_cells = 0;
  double cells(FootprintWidth width) const { return width == FootprintWidth::narrow ? narrow_cells : area_cells; }
};
std::optional<Footprint> footprintOn(const MipmapFootprint& mipmap, const Ray& camera_ray);

// The level of a path from its camera ray: by the nearest mipmap the ray meets (its footprint's width
// that the mipmap's `levels_by` names), drawing one uniform number only where two levels blend (so
// that scenes and pixels without a blend keep their random streams). A ray without spread (not from a
// camera) gets level 0, one that meets no mipmap the coarsest of any (what it reaches after a bounce
// is far or blurred).
int pathLevel(const std::vector<MipmapFootprint>& mipmaps, const Ray& camera_ray, RandomStream& rng);

}  // namespace vdbappear
