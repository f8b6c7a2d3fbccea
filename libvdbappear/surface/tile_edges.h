#pragma once
// What lies beyond a displacement map's edges when its micro-geometry is traced
// (prefilter/effective_brdf.h, MicroGeometry): nothing, or the map again.

namespace vdbappear {

enum class TileEdges {
  // The map alone: rays that leave it escape.
  Open,
  // The map as one tile of a surface tiled by it (Table 4.3's tiled models; the renderer's tiles
  // over a plane, a sphere or a mesh): a ray that leaves the tile enters it again across the
  // opposite edge, so each cell sees its neighbours across the seam as a tile among tiles does.
  // Needs a map that tiles seamlessly (every procedural map of the project does).
  Periodic,
};

}  // namespace vdbappear
